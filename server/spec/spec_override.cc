#include "server/spec/spec_override.h"

#include <google/protobuf/message.h>

#include <algorithm>
#include <nlohmann/json.hpp>
#include <set>

#include "server/spec/run_spec_json.h"
#include "shared/common/check.h"

namespace mbstream {

namespace {

using Json = nlohmann::json;

// "outputIntervalS" -> "output_interval_s"; proto names pass unchanged.
std::string ProtoName(const std::string& name) {
  std::string out;
  for (const char c : name) {
    if (c >= 'A' && c <= 'Z') {
      out += '_';
      out += static_cast<char>(c - 'A' + 'a');
    } else {
      out += c;
    }
  }
  return out;
}

// One step of a path: a field, and perhaps a list element by index or by key.
struct Step {
  std::string field;
  enum class Pick { kNone, kIndex, kKey } pick = Pick::kNone;
  size_t index = 0;
  std::string key, key_value;
};

std::vector<Step> ParsePath(const std::string& path, const std::string& where) {
  const auto fail = [&](const std::string& problem) -> InputError {
    return InputError(where + ": " + path + ": " + problem +
                      "; write fields as in the run spec's JSON, joined by '.', with [N] or "
                      "[KEY=VALUE] for a list's element, e.g. drives[joint=joint2].pd_servo.kp");
  };
  std::vector<Step> steps;
  size_t at = 0;
  while (at <= path.size()) {
    const size_t end = path.find_first_of(".[", at);
    Step step;
    step.field = ProtoName(path.substr(at, end == std::string::npos ? end : end - at));
    if (step.field.empty()) throw fail("a field name is missing");
    at = end == std::string::npos ? path.size() : end;
    if (at < path.size() && path[at] == '[') {
      const size_t close = path.find(']', at);
      if (close == std::string::npos) throw fail("a '[' is not closed");
      const std::string inside = path.substr(at + 1, close - at - 1);
      if (const size_t eq = inside.find('='); eq != std::string::npos) {
        step.pick = Step::Pick::kKey;
        step.key = ProtoName(inside.substr(0, eq));
        step.key_value = inside.substr(eq + 1);
        if (step.key.empty() || step.key_value.empty()) throw fail("[KEY=VALUE] needs both");
      } else {
        if (inside.empty() || inside.find_first_not_of("0123456789") != std::string::npos ||
            inside.size() > 9) {
          throw fail("[" + inside + "] is not a list index");
        }
        step.pick = Step::Pick::kIndex;
        step.index = std::stoul(inside);
      }
      at = close + 1;
    }
    steps.push_back(std::move(step));
    if (at == path.size()) break;
    if (path[at] != '.') throw fail("expected '.' after ']'");
    ++at;
  }
  return steps;
}

Json ParseValue(const std::string& value) {
  Json parsed = Json::parse(value, nullptr, /*allow_exceptions=*/false);
  return parsed.is_discarded() ? Json(value) : parsed;  // a bare word: a string
}

using google::protobuf::FieldDescriptor;
using google::protobuf::Message;
using google::protobuf::Reflection;

const FieldDescriptor* FindField(const Message& message, const std::string& name) {
  const google::protobuf::Descriptor* type = message.GetDescriptor();
  if (const FieldDescriptor* field = type->FindFieldByName(name)) return field;
  std::string fields;
  for (int i = 0; i < type->field_count(); ++i) {
    fields += (i ? ", " : "") + type->field(i)->name();
  }
  throw InputError("no field '" + name + "' in " + type->name() + " (its fields: " + fields + ")");
}

// Sets field `f` of `m` (element `index` of a list, or the field itself when index < 0)
// from `value`.
void SetScalar(Message* m, const FieldDescriptor* f, int index, const Json& value) {
  const Reflection* r = m->GetReflection();
  const auto want = [&](const char* what) {
    return InputError("is a " + std::string(f->type_name()) + " field; give " + what + ", not " +
                      value.dump().substr(0, 80));
  };
  switch (f->cpp_type()) {
    case FieldDescriptor::CPPTYPE_DOUBLE:
    case FieldDescriptor::CPPTYPE_FLOAT: {
      if (!value.is_number()) throw want("a number");
      const double x = value.get<double>();
      if (f->cpp_type() == FieldDescriptor::CPPTYPE_FLOAT) {
        index < 0 ? r->SetFloat(m, f, static_cast<float>(x))
                  : r->SetRepeatedFloat(m, f, index, static_cast<float>(x));
      } else {
        index < 0 ? r->SetDouble(m, f, x) : r->SetRepeatedDouble(m, f, index, x);
      }
      return;
    }
    case FieldDescriptor::CPPTYPE_INT32:
    case FieldDescriptor::CPPTYPE_INT64: {
      if (!value.is_number_integer()) throw want("a whole number");
      const int64_t x = value.get<int64_t>();
      if (f->cpp_type() == FieldDescriptor::CPPTYPE_INT32) {
        if (x < INT32_MIN || x > INT32_MAX) throw want("a 32-bit whole number");
        index < 0 ? r->SetInt32(m, f, static_cast<int32_t>(x))
                  : r->SetRepeatedInt32(m, f, index, static_cast<int32_t>(x));
      } else {
        index < 0 ? r->SetInt64(m, f, x) : r->SetRepeatedInt64(m, f, index, x);
      }
      return;
    }
    case FieldDescriptor::CPPTYPE_BOOL:
      if (!value.is_boolean()) throw want("true or false");
      index < 0 ? r->SetBool(m, f, value.get<bool>())
                : r->SetRepeatedBool(m, f, index, value.get<bool>());
      return;
    case FieldDescriptor::CPPTYPE_STRING:
      if (!value.is_string()) throw want("a string");
      index < 0 ? r->SetString(m, f, value.get<std::string>())
                : r->SetRepeatedString(m, f, index, value.get<std::string>());
      return;
    default:
      throw InputError("is a " + std::string(f->type_name()) +
                       " field: a sweep sets numbers, strings and booleans; name one of its "
                       "fields (PATH.FIELD)");
  }
}

// The element of list `f` of `m` that `step` picks.
int PickIndex(const Message& m, const FieldDescriptor* f, const Step& step) {
  const Reflection* r = m.GetReflection();
  const int size = r->FieldSize(m, f);
  if (step.pick == Step::Pick::kIndex) {
    if (step.index >= static_cast<size_t>(size)) {
      throw InputError(step.field + "[" + std::to_string(step.index) + "]: the base spec's " +
                       step.field + " has " + std::to_string(size) +
                       " elements; give them in the base spec");
    }
    return static_cast<int>(step.index);
  }
  if (f->cpp_type() == FieldDescriptor::CPPTYPE_MESSAGE) {
    for (int i = 0; i < size; ++i) {
      const Message& element = r->GetRepeatedMessage(m, f, i);
      const FieldDescriptor* key = element.GetDescriptor()->FindFieldByName(step.key);
      if (key != nullptr && key->cpp_type() == FieldDescriptor::CPPTYPE_STRING &&
          !key->is_repeated() &&
          element.GetReflection()->GetString(element, key) == step.key_value) {
        return i;
      }
    }
  }
  throw InputError(step.field + ": no element of the base spec's " + step.field + " has " +
                   step.key + " = " + step.key_value + "; give it in the base spec");
}

// The message field `f` of `m` to go into, refusing to switch a oneof to another member.
Message* Enter(Message* m, const FieldDescriptor* f) {
  const Reflection* r = m->GetReflection();
  if (const google::protobuf::OneofDescriptor* oneof = f->containing_oneof()) {
    const FieldDescriptor* current = r->GetOneofFieldDescriptor(*m, oneof);
    if (current != nullptr && current != f) {
      throw InputError(f->name() + ": the base spec gives " + current->name() + " there, not " +
                       f->name() + "; give a " + f->name() + " in the base spec to sweep it");
    }
  }
  return r->MutableMessage(m, f);
}

}  // namespace

void ApplySpecOverride(const std::string& path, const std::string& value, v1::RunSpec* spec,
                       const std::string& where) {
  constexpr size_t kMostValueBytes = 1000;
  const std::vector<Step> steps = ParsePath(path, where);
  try {
    if (value.size() > kMostValueBytes) {
      throw InputError("the value has " + std::to_string(value.size()) + " bytes, more than " +
                       std::to_string(kMostValueBytes));
    }
    const Json parsed = ParseValue(value);
    Message* m = spec;
    for (size_t i = 0; i < steps.size(); ++i) {
      const Step& step = steps[i];
      const bool last = i + 1 == steps.size();
      const FieldDescriptor* f = FindField(*m, step.field);
      const bool is_message = f->cpp_type() == FieldDescriptor::CPPTYPE_MESSAGE;
      if (step.pick != Step::Pick::kNone) {
        if (!f->is_repeated()) throw InputError(step.field + " is not a list");
        const int index = PickIndex(*m, f, step);
        if (last) {
          SetScalar(m, f, index, parsed);
        } else if (is_message) {
          m = m->GetReflection()->MutableRepeatedMessage(m, f, index);
        } else {
          throw InputError(step.field + "[...] is a value, not a message");
        }
      } else if (f->is_repeated()) {
        throw InputError(step.field + " is a list; name an element: " + step.field + "[N]");
      } else if (last) {
        SetScalar(m, f, -1, parsed);
      } else if (is_message) {
        m = Enter(m, f);
      } else {
        throw InputError(step.field + " is a value, not a message: nothing is inside it");
      }
    }
  } catch (const InputError& e) {
    throw InputError(where + ": " + path + ": " + e.what());
  }
}

SweepPoints GridPoints(const std::vector<std::string>& paths,
                       const std::vector<std::vector<std::string>>& values, long max_points,
                       const std::string& where) {
  SweepPoints sweep{paths, {}};
  std::set<std::string> seen;
  long count = 1;
  for (size_t a = 0; a < paths.size(); ++a) {
    if (!seen.insert(paths[a]).second) {
      throw InputError(where + ": " + paths[a] + " is swept twice; give each path once");
    }
    if (values[a].empty()) {
      throw InputError(where + ": " + paths[a] + " has no values; give at least one");
    }
    count *= static_cast<long>(values[a].size());
    if (count > max_points) {
      throw InputError(where + ": the grid has more than " + std::to_string(max_points) +
                       " points; sweep fewer values, or split the sweep");
    }
  }
  if (paths.empty()) return sweep;
  std::vector<size_t> at(paths.size(), 0);
  for (long k = 0; k < count; ++k) {
    std::vector<std::string>& point = sweep.points.emplace_back();
    for (size_t a = 0; a < paths.size(); ++a) point.push_back(values[a][at[a]]);
    for (size_t a = paths.size(); a-- > 0;) {  // the last axis varies fastest
      if (++at[a] < values[a].size()) break;
      at[a] = 0;
    }
  }
  return sweep;
}

std::vector<v1::RunSpec> ExpandSweep(const v1::RunSpec& base, const SweepPoints& sweep,
                                     const std::string& where, long first, long count) {
  const size_t begin = static_cast<size_t>(std::max(0L, first));
  const size_t end = count < 0 ? sweep.points.size()
                               : std::min(sweep.points.size(), begin + static_cast<size_t>(count));
  std::vector<v1::RunSpec> specs;
  specs.reserve(end > begin ? end - begin : 0);
  for (size_t k = begin; k < end; ++k) {
    const std::vector<std::string>& point = sweep.points[k];
    if (point.size() != sweep.paths.size()) {
      throw InputError(where + ": point " + std::to_string(k) + " has " +
                       std::to_string(point.size()) + " values for " +
                       std::to_string(sweep.paths.size()) + " paths; give one value per path");
    }
    std::string label;
    for (size_t a = 0; a < point.size(); ++a) {
      label += (a ? ", " : "") + sweep.paths[a] + "=" + point[a].substr(0, 40);
    }
    v1::RunSpec& spec = specs.emplace_back(base);
    for (size_t a = 0; a < point.size(); ++a) {
      ApplySpecOverride(sweep.paths[a], point[a], &spec,
                        where + ": point " + std::to_string(k) + " (" + label + ")");
    }
  }
  return specs;
}

}  // namespace mbstream
