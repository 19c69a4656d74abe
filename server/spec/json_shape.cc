#include "server/spec/json_shape.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <string_view>
#include <vector>

#include "shared/common/check.h"
#include "shared/common/utf8.h"

namespace mbstream {

namespace {

constexpr std::size_t kMaxDepth = 32;
constexpr std::size_t kMaxKeyBytes = 200;

// A SAX handler that keeps the path to the current value and stops at the first problem.
class ShapeHandler : public nlohmann::json_sax<nlohmann::json> {
 public:
  bool null() override {
    Enter();
    return !InList() || Fail("is null; give a number (a list holds numbers or objects only)");
  }
  bool boolean(bool) override { return Enter(); }
  bool number_integer(number_integer_t) override { return Enter(); }
  bool number_unsigned(number_unsigned_t) override { return Enter(); }
  bool number_float(number_float_t, const string_t&) override { return Enter(); }
  bool binary(binary_t&) override { return Enter(); }
  bool string(string_t& value) override {
    Enter();
    return value.find('\0') == std::string::npos ||
           Fail("holds a NUL character (\\u0000); remove it");
  }
  bool start_object(std::size_t) override { return Enter() && Open('{'); }
  bool end_object() override { return Close(); }
  bool start_array(std::size_t) override {
    Enter();
    if (InList()) return Fail("is a list inside a list; give a flat list of numbers");
    return Open('[');
  }
  bool end_array() override { return Close(); }
  bool key(string_t& key) override {
    if (key.size() > kMaxKeyBytes) {
      return Fail("has a key of " + std::to_string(key.size()) + " bytes ('" +
                  CutForMessage(key, 40) + "'); no RunSpec field has such a name: remove it");
    }
    path_.back().key = key;
    return true;
  }
  bool parse_error(std::size_t, const std::string&, const nlohmann::detail::exception&) override {
    return false;  // protobuf's parser reports malformed JSON in its own words
  }

  const std::string& problem() const { return problem_; }

 private:
  struct Level {
    char kind;        // '{' or '['
    std::string key;  // the current key of an object
    long index = -1;  // the current index of a list
  };

  // Called first for every value: a value in a list advances the list's index.
  bool Enter() {
    if (InList()) ++path_.back().index;
    return true;
  }
  bool InList() const { return !path_.empty() && path_.back().kind == '['; }
  bool Open(char kind) {
    if (path_.size() >= kMaxDepth) {
      return Fail("is nested more than " + std::to_string(kMaxDepth) +
                  " deep; a RunSpec nests 4 deep");
    }
    path_.push_back(Level{kind, "", -1});
    return true;
  }
  bool Close() {
    if (!path_.empty()) path_.pop_back();
    return true;
  }
  bool Fail(const std::string& what) {
    std::string where;
    for (const Level& level : path_) {
      if (level.kind == '{' && !level.key.empty()) {
        where += (where.empty() ? "" : ".") + CutForMessage(level.key, 40);
      } else if (level.kind == '[') {
        where += "[" + std::to_string(std::max(0L, level.index)) + "]";
      }
    }
    problem_ = (where.empty() ? std::string("the spec") : where) + " " + what;
    return false;
  }

  std::vector<Level> path_;
  std::string problem_;
};

}  // namespace

std::string CutForMessage(const std::string& text, std::size_t bytes) {
  if (text.size() <= bytes) return text;
  std::size_t end = bytes;
  // Back up to the start of a UTF-8 sequence (not a continuation byte 10xxxxxx).
  while (end > 0 && (static_cast<unsigned char>(text[end]) & 0xC0) == 0x80) --end;
  return text.substr(0, end) + "...";
}

void CheckJsonShape(const std::string& json, const std::string& source) {
  if (const auto bad = FirstInvalidUtf8(json)) {
    throw InputError(source + ": " + NotUtf8At(json, *bad) +
                     "; a run spec is UTF-8 JSON: convert the file or remove the byte");
  }
  ShapeHandler handler;
  nlohmann::json::sax_parse(json, &handler, nlohmann::json::input_format_t::json,
                            /*strict=*/true);
  if (!handler.problem().empty()) throw InputError(source + ": " + handler.problem());
}

}  // namespace mbstream
