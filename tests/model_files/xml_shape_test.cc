// The XML shape check that runs before TinyXML (shared/model_files/xml_shape.h): it counts what a
// URDF holds, passes comments, CDATA and declarations by, and stops at the first excess.
#include "shared/model_files/xml_shape.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

namespace mbstream::model_files {
namespace {

using ::testing::HasSubstr;

TEST(XmlShapeTest, CountsAWellShapedUrdf) {
  XmlShape shape;
  const auto problem = CheckXmlShape(
      "<?xml version=\"1.0\"?>\n<!-- <a><b><c> -->\n<robot name=\"r\">\n"
      "<link name=\"a\"><visual><geometry><mesh filename=\"x\"/></geometry></visual></link>\n"
      "<link name=\"b\"/><joint name=\"j\" type=\"fixed\"><parent link=\"a\"/>"
      "<child link=\"b\"/></joint><![CDATA[<x><y>]]>\n</robot>",
      XmlShapeLimits{}, &shape);
  EXPECT_FALSE(problem.has_value()) << problem->what;
  EXPECT_EQ(shape.depth, 4);  // robot, link, visual, geometry (mesh is empty)
  EXPECT_EQ(shape.top_links, 2);
  EXPECT_EQ(shape.top_joints, 1);
  EXPECT_EQ(shape.elements, 9);
}

TEST(XmlShapeTest, EachLimitStopsAtItsLine) {
  XmlShapeLimits limits;
  limits.max_depth = 3;
  limits.max_attributes = 2;
  limits.max_elements = 5;
  limits.max_top_links = 1;
  auto p = CheckXmlShape("<r>\n<a>\n<b>\n<c>", limits);
  ASSERT_TRUE(p);
  EXPECT_EQ(p->line, 4);
  EXPECT_THAT(p->what, HasSubstr("nested more than 3"));
  p = CheckXmlShape("<r>\n<a x='1' y=\"=\" z='2'/>", limits);
  ASSERT_TRUE(p);
  EXPECT_EQ(p->line, 2);
  EXPECT_THAT(p->what, HasSubstr("<a> has more than 2 attributes"));
  p = CheckXmlShape("<r><a/><a/><a/><a/><a/></r>", limits);
  ASSERT_TRUE(p);
  EXPECT_THAT(p->what, HasSubstr("more than 5 elements"));
  p = CheckXmlShape("<r><link/>\n<link/></r>", limits);
  ASSERT_TRUE(p);
  EXPECT_EQ(p->line, 2);
  EXPECT_TRUE(p->over_caller_limit);
  // A <link> deeper down is not a model's link.
  EXPECT_FALSE(CheckXmlShape("<r><link/><g><link/></g></r>", limits));
}

TEST(XmlShapeTest, EncodingsAreNamed) {
  EXPECT_THAT(CheckXmlShape(std::string("\xFE\xFF\0<", 4), {})->what, HasSubstr("UTF-16"));
  EXPECT_THAT(CheckXmlShape(std::string("<\0r\0", 4), {})->what, HasSubstr("UTF-16"));
  const auto nul = CheckXmlShape(std::string("<r>\n\n<a>\0</a></r>", 17), {});
  ASSERT_TRUE(nul);
  EXPECT_EQ(nul->line, 3);
  EXPECT_THAT(nul->what, HasSubstr("NUL byte"));
  const auto latin1 = CheckXmlShape("<r>\n<a n=\"caf\xE9\"/></r>", {});
  ASSERT_TRUE(latin1);
  EXPECT_EQ(latin1->line, 2);
  EXPECT_THAT(latin1->what, HasSubstr("byte 0xE9 is not UTF-8"));
  EXPECT_FALSE(CheckXmlShape("\xEF\xBB\xBF<r n=\"caf\xC3\xA9\"/>", {}));  // UTF-8 BOM, é
}

TEST(XmlShapeTest, EntitiesAreRefusedPlainDoctypesPass) {
  EXPECT_FALSE(CheckXmlShape("<!DOCTYPE r SYSTEM \"r.dtd\"><r/>", {}));
  const auto p =
      CheckXmlShape("<!DOCTYPE r [\n<!ELEMENT r ANY>\n<!ENTITY a \"]>\">]><r>&a;</r>", {});
  ASSERT_TRUE(p);
  EXPECT_EQ(p->line, 3);
  EXPECT_THAT(p->what, HasSubstr("declares entities"));
}

TEST(XmlShapeTest, UnterminatedMarkupIsLeftToTheParser) {
  EXPECT_FALSE(CheckXmlShape("<r><!-- never closed", {}));
  EXPECT_FALSE(CheckXmlShape("<r a=\"1", {}));
  EXPECT_FALSE(CheckXmlShape("", {}));
}

}  // namespace
}  // namespace mbstream::model_files
