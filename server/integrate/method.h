// The time-integration methods of the contract and their names.
#pragma once

#include <string>

namespace mbstream {

// The time integrator.
enum class Method {
  kBdf,    // CVODE BDF (variable order 1-5), Newton with dense Jacobian
  kAdams,  // CVODE Adams-Moulton (orders 1-12), functional iteration
  kErk,    // ARKODE explicit Runge-Kutta (table in RunConfig::erk_table)
  kDirk,   // ARKODE diagonally implicit Runge-Kutta
  kIda,    // IDA (DAE formulations)
  kRk4,    // fixed-step classical Runge-Kutta 4
  kEuler,  // fixed-step semi-implicit (symplectic) Euler, the game-engine baseline
};

const char* MethodName(Method method);  // "bdf", "adams", ...
// Parses the name of the contract; returns false for an unknown name.
bool ParseMethod(const std::string& name, Method* method);

}  // namespace mbstream
