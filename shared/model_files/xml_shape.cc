#include "shared/model_files/xml_shape.h"

#include <algorithm>
#include <utility>

#include "shared/common/utf8.h"

namespace mbstream::model_files {

namespace {

using Problem = std::optional<XmlShapeProblem>;

bool IsNameEnd(char c) {
  return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '/' || c == '>';
}

class ShapeScan {
 public:
  ShapeScan(std::string_view text, const XmlShapeLimits& limits) : text_(text), limits_(limits) {}

  Problem Run() {
    if (Problem p = CheckEncoding()) return p;
    std::size_t i = 0;
    while ((i = text_.find('<', i)) != std::string_view::npos) {
      const std::string_view rest = text_.substr(i);
      std::size_t next = std::string_view::npos;
      if (rest.starts_with("<!--")) {
        next = Skip(i + 4, "-->");
      } else if (rest.starts_with("<![CDATA[")) {
        next = Skip(i + 9, "]]>");
      } else if (rest.starts_with("<?")) {
        next = Skip(i + 2, "?>");
      } else if (rest.starts_with("<!")) {
        if (Problem p = Declaration(i, &next)) return p;
      } else if (rest.starts_with("</")) {
        depth_ = std::max(0, depth_ - 1);
        next = Skip(i + 2, ">");
      } else {
        if (Problem p = StartTag(i, &next)) return p;
      }
      if (next == std::string_view::npos) break;  // unterminated: the parser says where
      i = next;
    }
    return std::nullopt;
  }

  const XmlShape& shape() const { return shape_; }

 private:
  // The position after `end` found from `from`, or npos.
  std::size_t Skip(std::size_t from, std::string_view end) const {
    const std::size_t at = text_.find(end, from);
    return at == std::string_view::npos ? at : at + end.size();
  }

  XmlShapeProblem At(std::size_t at, std::string what) const {
    const auto newlines = std::count(text_.begin(), text_.begin() + at, '\n');
    return XmlShapeProblem{static_cast<int>(1 + newlines), std::move(what)};
  }

  Problem CheckEncoding() const {
    const auto byte = [&](std::size_t k) {
      return k < text_.size() ? static_cast<unsigned char>(text_[k]) : 0x100;
    };
    const bool utf16_bom =
        (byte(0) == 0xFF && byte(1) == 0xFE) || (byte(0) == 0xFE && byte(1) == 0xFF);
    const std::size_t nul = text_.find('\0');
    if (utf16_bom || (nul != std::string_view::npos && nul < 4)) {
      return At(0,
                "the file is UTF-16 or UTF-32 (a byte-order mark or NUL bytes at its start); "
                "mbstream reads XML in UTF-8: convert it, e.g. iconv -f UTF-16 -t UTF-8");
    }
    if (nul != std::string_view::npos) {
      return At(nul, "a NUL byte, which XML cannot hold; remove it (is the file binary?)");
    }
    if (const auto bad = FirstInvalidUtf8(text_)) {
      const std::string where = NotUtf8At(text_, *bad);  // "line N: byte 0xHH is not UTF-8"
      return At(*bad, where.substr(where.find(": ") + 2) +
                          "; mbstream reads XML in UTF-8: convert the file (e.g. iconv -f "
                          "LATIN1 -t UTF-8) or remove the byte");
    }
    return std::nullopt;
  }

  // A declaration <!...>: a DOCTYPE's internal subset may hold <!ENTITY>, which TinyXML does
  // not expand (an entity reference would silently read as text) and an attacker uses to
  // blow up a document: refused.
  Problem Declaration(std::size_t at, std::size_t* next) const {
    int brackets = 0;
    char quote = 0;
    for (std::size_t k = at + 2; k < text_.size(); ++k) {
      const char c = text_[k];
      if (quote != 0) {
        if (c == quote) quote = 0;
      } else if (c == '"' || c == '\'') {
        quote = c;
      } else if (c == '[') {
        ++brackets;
      } else if (c == ']') {
        --brackets;
      } else if (c == '<' && text_.substr(k).starts_with("<!ENTITY")) {
        return At(k,
                  "the <!DOCTYPE> declares entities, which mbstream does not expand; "
                  "remove the DOCTYPE and write the values in place");
      } else if (c == '>' && brackets <= 0) {
        *next = k + 1;
        return std::nullopt;
      }
    }
    *next = std::string_view::npos;
    return std::nullopt;
  }

  Problem StartTag(std::size_t at, std::size_t* next) {
    if (++shape_.elements > limits_.max_elements) {
      return At(at,
                "more than " + std::to_string(limits_.max_elements) +
                    " elements in the document, the limit; a robot description needs far fewer: " +
                    "is the file generated in a loop?");
    }
    std::size_t k = at + 1;
    while (k < text_.size() && !IsNameEnd(text_[k])) ++k;
    const std::string_view name = text_.substr(at + 1, k - at - 1);
    int attributes = 0;
    char quote = 0;
    for (; k < text_.size(); ++k) {
      const char c = text_[k];
      if (quote != 0) {
        if (c == quote) quote = 0;
      } else if (c == '"' || c == '\'') {
        quote = c;
      } else if (c == '=') {
        if (++attributes > limits_.max_attributes) {
          return At(at, "element <" + std::string(name.substr(0, 64)) + "> has more " + "than " +
                            std::to_string(limits_.max_attributes) + " attributes, the limit; " +
                            "a URDF element has at most 6: remove the extra attributes");
        }
      } else if (c == '>') {
        break;
      }
    }
    if (k >= text_.size()) {
      *next = std::string_view::npos;
      return std::nullopt;
    }
    *next = k + 1;
    if (!limits_.refused_element.empty() && name == limits_.refused_element) {
      return At(at, "<" + std::string(name) +
                        "> is not read by mbstream: " + std::string(limits_.refused_note));
    }
    if ((depth_ == 1 || limits_.links_at_any_depth) && name == "link" &&
        ++shape_.top_links > limits_.max_top_links) {
      XmlShapeProblem problem = At(at, "more than " + std::to_string(limits_.max_top_links) +
                                           " <link> elements, the limit (--max-links); split "
                                           "the model or raise the limit");
      problem.over_caller_limit = true;
      return problem;
    }
    if (depth_ == 1 && name == "joint") ++shape_.top_joints;
    if (text_[k - 1] == '/') return std::nullopt;  // <empty/>
    if (++depth_ > limits_.max_depth) {
      return At(at, "elements nested more than " + std::to_string(limits_.max_depth) +
                        " deep, the limit; " + std::string(limits_.nesting_note) +
                        ": close the elements left open or remove the extra nesting");
    }
    shape_.depth = std::max(shape_.depth, depth_);
    return std::nullopt;
  }

  std::string_view text_;
  const XmlShapeLimits& limits_;
  XmlShape shape_;
  int depth_ = 0;
};

}  // namespace

std::optional<XmlShapeProblem> CheckXmlShape(std::string_view text, const XmlShapeLimits& limits,
                                             XmlShape* shape) {
  ShapeScan scan(text, limits);
  Problem problem = scan.Run();
  if (shape != nullptr) *shape = scan.shape();
  return problem;
}

}  // namespace mbstream::model_files
