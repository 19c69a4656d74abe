// The ARKODE Butcher tables a run may name: short names ("dormand-prince", "sdirk", ...)
// and ARKODE's own names ("ARKODE_VERNER_8_5_6", ...), matched without regard to case.
#pragma once

#include <span>
#include <string>

namespace mbstream {

struct ButcherTableInfo {
  const char* alias;        // the short name, or "" when the table has none
  const char* arkode_name;  // ARKODE's name, e.g. "ARKODE_DORMAND_PRINCE_7_4_5"
  int id;                   // its ARKODE_ERKTableID or ARKODE_DIRKTableID
  const char* display;      // for Integrator::name(), e.g. "Dormand-Prince 7-4-5"
  int order;                // the order of the method (the embedding is one lower or so)
};

// The explicit table called `name` ("" = the default, Dormand-Prince 7-4-5, order 5).
// Throws InputError listing the accepted names when there is none.
const ButcherTableInfo& FindErkTable(const std::string& name);

// The diagonally implicit table called `name` ("" = the default, Kvaerno 5-3-4, order 4,
// L-stable). Throws InputError listing the accepted names when there is none.
const ButcherTableInfo& FindDirkTable(const std::string& name);

// Every table, the default first.
std::span<const ButcherTableInfo> ErkTables();
std::span<const ButcherTableInfo> DirkTables();

// The accepted names, comma-separated: short names first, then ARKODE's.
std::string ErkTableNames();
std::string DirkTableNames();

}  // namespace mbstream
