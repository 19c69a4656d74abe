// RunSpec <-> JSON text, with protobuf's own JSON mapping.
#include "server/spec/run_spec_json.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <google/protobuf/descriptor.h>
#include <google/protobuf/util/json_util.h>

#include "server/spec/json_shape.h"
#include "shared/common/check.h"
#include "shared/common/did_you_mean.h"

namespace mbstream {

namespace {

// The field names of `descriptor` and of the messages it holds, once each.
void FieldNames(const google::protobuf::Descriptor* descriptor, std::vector<std::string>* names,
                std::vector<const google::protobuf::Descriptor*>* seen) {
  if (std::find(seen->begin(), seen->end(), descriptor) != seen->end()) return;
  seen->push_back(descriptor);
  for (int i = 0; i < descriptor->field_count(); ++i) {
    const google::protobuf::FieldDescriptor* field = descriptor->field(i);
    names->push_back(field->name());
    if (field->message_type() != nullptr) FieldNames(field->message_type(), names, seen);
  }
}

// Protobuf's "[(PATH) ]NAME: Cannot find field.": "; did you mean 'FIELD'?" for the closest
// field name of a RunSpec (its nested messages' too), or "".
std::string FieldDidYouMean(const std::string& message) {
  const size_t end = message.find(": Cannot find field");
  if (end == std::string::npos || end > 300) return "";
  const size_t start = message.find_last_of(" )", end);
  const std::string name = message.substr(start == std::string::npos ? 0 : start + 1,
                                          end - (start == std::string::npos ? 0 : start + 1));
  std::vector<std::string> names;
  std::vector<const google::protobuf::Descriptor*> seen;
  FieldNames(v1::RunSpec::descriptor(), &names, &seen);
  return DidYouMean(name, names);
}

}  // namespace

v1::RunSpec ParseRunSpecJson(const std::string& json, const std::string& source) {
  CheckJsonShape(json, source);
  google::protobuf::util::JsonParseOptions options;
  options.ignore_unknown_fields = false;
  v1::RunSpec spec;
  const auto status = google::protobuf::util::JsonStringToMessage(json, &spec, options);
  if (!status.ok()) {
    // Cut: the message quotes an unknown key whole, and a key may be megabytes long.
    const std::string message(status.message());
    throw InputError(source + ": invalid JSON/RunSpec: " + CutForMessage(message, 400) +
                     FieldDidYouMean(message) +
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
