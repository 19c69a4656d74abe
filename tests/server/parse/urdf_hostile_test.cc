// Hostile URDFs (issue 36): nesting, attribute floods, huge chains, names and encodings that
// once crashed the importer, hung it or got misleading messages. Each is refused before any
// recursive walk with the file, the line and what to do.
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "server/parse/urdf_import.h"
#include "shared/common/check.h"
#include "tests/server/parse/urdf_test_util.h"

namespace mbstream {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;
using testing::ImportError;
using testing::JointXml;
using testing::LinkXml;
using testing::OneJoint;
using testing::Robot;

std::string Repeat(const std::string& text, int times) {
  std::string out;
  out.reserve(text.size() * times);
  for (int i = 0; i < times; ++i) out += text;
  return out;
}

TEST(UrdfHostileTest, DeepNestingIsRefusedBeforeTheParserRecurses) {
  const std::string deep = "<robot name=\"d\"><link name=\"a\"/>\n" + Repeat("<foo>", 200000) +
                           Repeat("</foo>", 200000) + "</robot>";
  EXPECT_THAT(ImportError(deep), AllOf(HasSubstr("bad.urdf:2: elements nested more than 64"),
                                       HasSubstr("remove the extra nesting")));
  // Nested <link> elements, as in the report.
  EXPECT_THAT(ImportError("<robot name=\"d\">" + Repeat("<link name=\"x\">", 100000) +
                          Repeat("</link>", 100000) + "</robot>"),
              HasSubstr("nested more than 64"));
}

TEST(UrdfHostileTest, AnAttributeFloodIsRefusedInLinearTime) {
  std::string flood = "<robot name=\"r\">\n<link name=\"base\"";
  for (int i = 0; i < 100000; ++i) flood += " a" + std::to_string(i) + "=\"1\"";
  flood += "/>\n</robot>";
  EXPECT_THAT(ImportError(flood), AllOf(HasSubstr("bad.urdf:2: element <link> has more than 256 "
                                                  "attributes"),
                                        HasSubstr("remove the extra attributes")));
}

TEST(UrdfHostileTest, AHugeChainIsALimitErrorBeforeAnyParse) {
  std::string chain;
  for (int i = 1; i <= 300; ++i) {
    const std::string parent = i == 1 ? "base" : "l" + std::to_string(i - 1);
    chain += LinkXml("l" + std::to_string(i)) +
             JointXml("f" + std::to_string(i), "fixed", parent, "l" + std::to_string(i), "");
  }
  try {
    ImportUrdf(Robot(chain), "chain.urdf", {}, UrdfImportOptions{.max_links = 256});
    FAIL() << "no LimitError";
  } catch (const LimitError& e) {
    EXPECT_THAT(e.what(), AllOf(HasSubstr("chain.urdf:"), HasSubstr("more than 256 <link>"),
                                HasSubstr("--max-links")));
  }
  // Within the limit it imports (the fixed links merge into the base).
  EXPECT_NO_THROW(ImportUrdf(Robot(chain), "chain.urdf", {}, {.max_links = 400}));
}

TEST(UrdfHostileTest, TheReadersCeilingHoldsWithoutACallerLimit) {
  std::string links = "<robot name=\"r\">\n";
  for (int i = 0; i <= 100000; ++i) links += "<link name=\"l" + std::to_string(i) + "\"/>";
  EXPECT_THROW(ImportUrdf(links + "</robot>", "many.urdf", {}), LimitError);
}

TEST(UrdfHostileTest, EmptyOrControlCharacterNamesAreRefusedWithTheLine) {
  EXPECT_THAT(ImportError(Robot(LinkXml("link1") + JointXml("", "revolute", "base", "link1"))),
              AllOf(HasSubstr("bad.urdf:4: joint name is empty"), HasSubstr("unique printable")));
  EXPECT_THAT(ImportError(Robot(LinkXml("link1") + JointXml("&#0;", "revolute", "base", "link1"))),
              HasSubstr("bad.urdf:4: joint name is empty"));
  EXPECT_THAT(ImportError(Robot(LinkXml("&#1;"))), HasSubstr("link name holds a control"));
}

TEST(UrdfHostileTest, BytesThatAreNotUtf8AreRefusedWithTheLine) {
  EXPECT_THAT(ImportError(Robot(LinkXml("link1") + JointXml("j\xFF", "revolute", "base", "link1"))),
              AllOf(HasSubstr("bad.urdf:4: byte 0xFF is not UTF-8"), HasSubstr("iconv")));
}

TEST(UrdfHostileTest, Utf16IsNamedAsSuch) {
  std::string utf16 = "\xFF\xFE";
  for (char c : OneJoint()) utf16 += std::string(1, c) + '\0';
  EXPECT_THAT(ImportError(utf16), AllOf(HasSubstr("bad.urdf:1: the file is UTF-16"),
                                        HasSubstr("iconv -f UTF-16 -t UTF-8")));
}

TEST(UrdfHostileTest, ADoctypeWithEntitiesIsNamed) {
  const std::string text =
      "<?xml version=\"1.0\"?>\n<!DOCTYPE robot [\n<!ENTITY x \"1\">\n]>\n" + OneJoint();
  EXPECT_THAT(ImportError(text), AllOf(HasSubstr("bad.urdf:3: the <!DOCTYPE> declares entities"),
                                       HasSubstr("remove the DOCTYPE")));
  // A DOCTYPE without entities is harmless.
  EXPECT_NO_THROW(ImportUrdf("<!DOCTYPE robot>\n" + OneJoint(), "ok.urdf", {}));
}

}  // namespace
}  // namespace mbstream
