// RunSpec <-> JSON text, with protobuf's own JSON mapping.
#include "server/spec/run_spec_json.h"

#include <filesystem>
#include <fstream>
#include <sstream>

#include <google/protobuf/util/json_util.h>

#include "common/check.h"
#include "server/spec/json_shape.h"

namespace mbstream {

v1::RunSpec ParseRunSpecJson(const std::string& json, const std::string& source) {
  CheckJsonShape(json, source);
  google::protobuf::util::JsonParseOptions options;
  options.ignore_unknown_fields = false;
  v1::RunSpec spec;
  const auto status = google::protobuf::util::JsonStringToMessage(json, &spec, options);
  if (!status.ok()) {
    // Cut: the message quotes an unknown key whole, and a key may be megabytes long.
    throw InputError(
        source + ": invalid JSON/RunSpec: " + CutForMessage(std::string(status.message()), 400) +
        "; see models/irb1600/seed-run.json for an example");
  }
  return spec;
}

v1::RunSpec LoadRunSpecFile(const std::string& path) {
  std::error_code error;
  if (!std::filesystem::is_regular_file(path, error)) {
    throw InputError(
        path + ": cannot read the run spec: no such file (or not a regular file); check the path");
  }
  std::ifstream file(path, std::ios::binary);
  std::ostringstream text;
  text << file.rdbuf();
  if (!file.is_open() || file.bad()) {
    throw InputError(path + ": cannot read the run spec; check the file's permissions");
  }
  return ParseRunSpecJson(text.str(), path);
}

std::string RunSpecToJson(const v1::RunSpec& spec) {
  google::protobuf::util::JsonPrintOptions options;
  options.add_whitespace = true;
  options.always_print_primitive_fields = true;
  options.preserve_proto_field_names = true;
  std::string json;
  const auto status = google::protobuf::util::MessageToJsonString(spec, &json, options);
  MBSTREAM_CHECK_MSG(status.ok(), "printing a RunSpec as JSON: " + status.ToString());
  return json;
}

}  // namespace mbstream
