// SDFormat import: the spanning tree chosen breadth-first from the world, the cut joints,
// poses relative to frames, inertials; errors with FILE:LINE; URDF or SDFormat by content.
#include "server/parse/sdf_import.h"

#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <string>

#include "server/parse/model_file.h"
#include "shared/common/check.h"

namespace mbstream {
namespace {

const std::string kFourBar = std::string(MBSTREAM_SOURCE_DIR) + "/models/linkages/four_bar.sdf";
const std::string kSliderCrank =
    std::string(MBSTREAM_SOURCE_DIR) + "/models/linkages/slider_crank.sdf";

std::vector<std::string> JointNamesOf(const Model& model) {
  std::vector<std::string> names;
  for (const Body& body : model.bodies) names.push_back(body.joint.name);
  return names;
}

TEST(SdfImportTest, FourBarTreeIsBreadthFirstFromTheWorldAndItsLoopIsCut) {
  const SdfImport sdf = ImportSdfFile(kFourBar);
  const Model& model = sdf.model;
  EXPECT_EQ(model.name, "four_bar");
  EXPECT_EQ(JointNamesOf(model),
            (std::vector<std::string>{"crank_joint", "rocker_joint", "coupler_joint"}));
  ASSERT_EQ(sdf.loops.size(), 1u);
  const LoopClosure& loop = sdf.loops[0];
  EXPECT_EQ(loop.name, "loop_joint");
  EXPECT_EQ(loop.type, LoopJointType::kRevolute);
  EXPECT_EQ(loop.body_a, model.FindBody("coupler"));
  EXPECT_EQ(loop.body_b, model.FindBody("rocker"));
  EXPECT_NE(loop.where.find("four_bar.sdf:"), std::string::npos) << loop.where;
  // Poses: the coupler's pin sits 0.1 m along the crank; the loop's pin 0.35 m along the
  // coupler and 0.3 m along the rocker; each axis -y, the same in every link's frame.
  const Body& coupler = model.bodies[model.FindBody("coupler")];
  EXPECT_LT((coupler.joint.X_PJ.p - Vector3d(0.1, 0, 0)).norm(), 1e-15);
  EXPECT_LT((coupler.joint.axis - Vector3d(0, -1, 0)).norm(), 1e-15);
  EXPECT_LT((loop.X_AJ.p - Vector3d(0.35, 0, 0)).norm(), 1e-15);
  EXPECT_LT((loop.X_BJ.p - Vector3d(0.3, 0, 0)).norm(), 1e-15);
  EXPECT_LT((loop.axis - Vector3d(0, -1, 0)).norm(), 1e-15);
  // Inertials: bars with their centre of mass half-way along.
  const RigidInertia& crank = model.bodies[model.FindBody("crank")].inertia;
  EXPECT_DOUBLE_EQ(crank.mass, 0.5);
  EXPECT_LT((crank.com - Vector3d(0.05, 0, 0)).norm(), 1e-15);
  EXPECT_NEAR(crank.inertia_com(1, 1), 0.5 * (0.01 + 0.0004) / 12, 1e-15);
}

TEST(SdfImportTest, SliderCrankHasAPrismaticJointInItsTree) {
  const SdfImport sdf = ImportSdfFile(kSliderCrank);
  EXPECT_EQ(JointNamesOf(sdf.model),
            (std::vector<std::string>{"crank_joint", "slider_joint", "rod_joint"}));
  const Joint& slider = sdf.model.bodies[1].joint;
  EXPECT_EQ(slider.type, JointType::kPrismatic);
  EXPECT_LT((slider.axis - Vector3d::UnitX()).norm(), 1e-15);
  ASSERT_EQ(sdf.loops.size(), 1u);
  EXPECT_EQ(sdf.loops[0].name, "pin_joint");
}

std::string Model(const std::string& body) {
  return "<?xml version=\"1.0\"?>\n<sdf version=\"1.7\">\n  <model name=\"m\">\n" + body +
         "  </model>\n</sdf>\n";
}

void ExpectImportError(const std::string& text, const std::string& words) {
  try {
    ImportSdf(text, "m.sdf");
    ADD_FAILURE() << "imported; expected: " << words;
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find(words), std::string::npos) << error.what();
  }
}

TEST(SdfImportTest, ErrorsNameTheFileAndLine) {
  ExpectImportError(Model("    <link name=\"a\"/>\n"
                          "    <link name=\"b\"/>\n"
                          "    <joint name=\"j\" type=\"fixed\"><parent>world</parent>"
                          "<child>a</child></joint>\n"),
                    "m.sdf:5: link 'b' is not reached from the world");
  ExpectImportError(Model("    <link name=\"a\"/>\n"
                          "    <joint name=\"j\" type=\"universal\"><parent>world</parent>"
                          "<child>a</child></joint>\n"),
                    "m.sdf:5: joint 'j': this joint type is not simulated by mbstream");
  ExpectImportError(
      "<?xml version=\"1.0\"?>\n<sdf version=\"1.7\">\n<world name=\"a\"/>\n"
      "<world name=\"b\"/>\n</sdf>\n",
      "m.sdf: the file has 2 worlds");
  ExpectImportError(
      "<?xml version=\"1.0\"?>\n<sdf version=\"1.7\">\n  <model name=\"m\">\n"
      "    <link name=\"a\">\n  </model>\n</sdf>\n",
      "m.sdf");
}

// The URDF reader's shape check and link limit, before libsdformat parses anything.
TEST(SdfImportTest, TheXmlShapeAndTheLinkLimitAreCheckedBeforeTheParse) {
  const auto message = [](const std::string& text, const SdfImportOptions& options = {}) {
    try {
      ImportSdf(text, "m.sdf", options);
    } catch (const LimitError& error) {
      return std::string("limit: ") + error.what();
    } catch (const InputError& error) {
      return std::string(error.what());
    }
    return std::string("accepted");
  };
  std::string deep = "<sdf version=\"1.7\">\n<model name=\"m\">\n";
  for (int i = 0; i < 70; ++i) deep += "<link name=\"x\">";
  EXPECT_EQ(message(deep).rfind("m.sdf:3: elements nested more than 64 deep", 0), 0u)
      << message(deep);
  const std::string entities =
      "<!DOCTYPE sdf [<!ENTITY e \"x\">]>\n<sdf version=\"1.7\"><model name=\"m\"/></sdf>";
  EXPECT_NE(message(entities).find("m.sdf:1: the <!DOCTYPE> declares entities"), std::string::npos)
      << message(entities);
  // <include> would make libsdformat read a file of the reading machine (or a URL).
  for (const char* uri : {"file:///etc/passwd", "model://m", "https://example.invalid/m"}) {
    const std::string include = "<sdf version=\"1.7\">\n<model name=\"m\"><link name=\"a\"/>\n" +
                                std::string("<include><uri>") + uri + "</uri></include>\n" +
                                "</model></sdf>\n";
    EXPECT_EQ(message(include).rfind(
                  "m.sdf:3: <include> is not read by mbstream: the server reads no file", 0),
              0u)
        << message(include);
  }
  const std::string utf16("\xff\xfe<\0s\0d\0f\0", 10);
  EXPECT_NE(message(utf16).find("UTF-16"), std::string::npos) << message(utf16);
  // The four-bar has 3 links: over a limit of 2 it is a LimitError naming --max-links, at 3
  // it imports (links in a <model> count, not only the root's children as in URDF).
  std::ifstream in(kFourBar);
  const std::string four_bar((std::istreambuf_iterator<char>(in)), {});
  const std::string over = message(four_bar, SdfImportOptions{.max_links = 2});
  EXPECT_EQ(over.rfind("limit: m.sdf:", 0), 0u) << over;
  EXPECT_NE(over.find("more than 2 <link> elements, the limit (--max-links)"), std::string::npos);
  EXPECT_EQ(message(four_bar, SdfImportOptions{.max_links = 3}), "accepted");
}

TEST(ModelFileTest, TellsUrdfFromSdformatByContent) {
  EXPECT_EQ(DetectModelFormat("<?xml version=\"1.0\"?>\n<!-- <sdf> -->\n<robot name=\"r\"/>"),
            ModelFormat::kUrdf);
  EXPECT_EQ(DetectModelFormat("<sdf version=\"1.7\"><model name=\"m\"/></sdf>"), ModelFormat::kSdf);
  // Anything else goes to the URDF reader, whose messages name what is wrong.
  EXPECT_EQ(DetectModelFormat("<sdformat/>"), ModelFormat::kUrdf);
  EXPECT_EQ(DetectModelFormat("not xml"), ModelFormat::kUrdf);
  const ModelFileImport sdf = ImportModelFile(kFourBar);
  EXPECT_EQ(sdf.format, ModelFormat::kSdf);
  EXPECT_EQ(sdf.loops.size(), 1u);
  const ModelFileImport urdf =
      ImportModelFile(std::string(MBSTREAM_SOURCE_DIR) + "/models/irb1600/irb1600.urdf");
  EXPECT_EQ(urdf.format, ModelFormat::kUrdf);
  EXPECT_EQ(urdf.model.num_dofs(), 6);
  EXPECT_TRUE(urdf.loops.empty());
}

}  // namespace
}  // namespace mbstream
