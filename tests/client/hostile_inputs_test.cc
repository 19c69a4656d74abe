// The regression corpus of issue 36: models and run specs that once crashed, hung or
// exhausted mbstream, each sent as a user would, to `mbstream simulate` and to a live
// server (`mbstream submit`, `mbstream run --spec`). Both must refuse it with the same
// message and exit 2 (INVALID_ARGUMENT or RESOURCE_EXHAUSTED), and the server must still
// answer afterwards.
#include <gmock/gmock.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <random>
#include <string>

#include "tests/common/server_process.h"

namespace mbstream::testing {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using ::testing::Not;

std::string Repeat(const std::string& text, int times) {
  std::string out;
  out.reserve(text.size() * times);
  for (int i = 0; i < times; ++i) out += text;
  return out;
}

// A base link and one revolute joint named `joint` (written as given, escapes and all).
std::string OneJointNamed(const std::string& joint) {
  return "<robot name=\"r\">\n<link name=\"base\"/>\n<link name=\"l1\"><inertial><mass "
         "value=\"1\"/><inertia ixx=\"1\" iyy=\"1\" izz=\"1\" ixy=\"0\" ixz=\"0\" iyz=\"0\"/>"
         "</inertial></link>\n<joint name=\"" +
         joint +
         "\" type=\"continuous\"><parent link=\"base\"/><child link=\"l1\"/><axis xyz=\"0 0 "
         "1\"/></joint>\n</robot>\n";
}

std::string FixedChain(int links) {
  std::string text = "<robot name=\"chain\">\n<link name=\"l0\"/>\n";
  for (int i = 1; i <= links; ++i) {
    text += "<link name=\"l" + std::to_string(i) + "\"/><joint name=\"f" + std::to_string(i) +
            "\" type=\"fixed\"><parent link=\"l" + std::to_string(i - 1) + "\"/><child link=\"l" +
            std::to_string(i) + "\"/></joint>\n";
  }
  return text + "</robot>\n";
}

// An SDFormat model of `links` links, each a fixed child of the one before (issue 31: the
// SDFormat reader holds the URDF reader's limits).
std::string SdfFixedChain(int links) {
  std::string text = "<sdf version=\"1.7\">\n<model name=\"chain\">\n<link name=\"l0\"/>\n";
  for (int i = 1; i <= links; ++i) {
    text += "<link name=\"l" + std::to_string(i) + "\"/><joint name=\"f" + std::to_string(i) +
            "\" type=\"fixed\"><parent>l" + std::to_string(i - 1) + "</parent><child>l" +
            std::to_string(i) + "</child></joint>\n";
  }
  return text + "</model>\n</sdf>\n";
}

struct HostileModel {
  const char* name;
  std::function<std::string()> text;
  std::string message;              // in both the CLI's and the server's answer
  const char* extension = ".urdf";  // the content decides the format; the name is a user's
};

const HostileModel kModels[] = {
    {"nested_foo",
     [] {
       return "<robot name=\"d\"><link name=\"a\"/>" + Repeat("<foo>", 200000) +
              Repeat("</foo>", 200000) + "</robot>";
     },
     "elements nested more than 64 deep"},
    {"nested_links",
     [] {
       return "<robot name=\"d\">" + Repeat("<link name=\"x\">", 100000) +
              Repeat("</link>", 100000) + "</robot>";
     },
     "elements nested more than 64 deep"},
    {"attribute_flood",
     [] {
       std::string text = "<robot name=\"r\"><link name=\"a\"";
       for (int i = 0; i < 100000; ++i) text += " a" + std::to_string(i) + "=\"1\"";
       return text + "/></robot>";
     },
     "has more than 256 attributes"},
    {"fixed_chain_200k", [] { return FixedChain(200000); }, "more than 256 <link> elements"},
    {"empty_joint_name", [] { return OneJointNamed(""); }, ":4: joint name is empty"},
    {"nul_joint_name", [] { return OneJointNamed("&#0;"); }, ":4: joint name is empty"},
    {"doctype_entities",
     [] { return "<!DOCTYPE robot [\n<!ENTITY e \"x\">\n]>\n" + OneJointNamed("j"); },
     ":2: the <!DOCTYPE> declares entities"},
    // The same checks before libsdformat (TinyXML2) parses an SDFormat file.
    {"sdf_nested",
     [] {
       return "<sdf version=\"1.7\"><model name=\"m\">" + Repeat("<foo>", 200000) +
              Repeat("</foo>", 200000) + "</model></sdf>";
     },
     "elements nested more than 64 deep, the limit; an SDFormat model nests about 8 deep", ".sdf"},
    {"sdf_attribute_flood",
     [] {
       std::string text = "<sdf version=\"1.7\"><model name=\"m\"><link name=\"a\"";
       for (int i = 0; i < 100000; ++i) text += " a" + std::to_string(i) + "=\"1\"";
       return text + "/></model></sdf>";
     },
     "has more than 256 attributes", ".sdf"},
    {"sdf_chain_200k", [] { return SdfFixedChain(200000); }, "more than 256 <link> elements",
     ".sdf"},
    {"sdf_chain_300", [] { return SdfFixedChain(300); }, ":259: more than 256 <link> elements",
     ".sdf"},
    {"sdf_doctype_entities",
     [] {
       return "<!DOCTYPE sdf [\n<!ENTITY e \"x\">\n]>\n<sdf version=\"1.7\"><model "
              "name=\"m\"><link name=\"a\"/></model></sdf>\n";
     },
     ":2: the <!DOCTYPE> declares entities", ".sdf"},
};

class HostileInputsTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    std::random_device random;
    dir_ =
        new fs::path(fs::temp_directory_path() / ("mbstream-hostile-" + std::to_string(random())));
    fs::create_directories(*dir_);
    server_ = new ServerProcess(MBSTREAM_SERVER, (*dir_ / "data").string());
  }
  static void TearDownTestSuite() {
    delete server_;
    fs::remove_all(*dir_);
    delete dir_;
  }
  static std::string Write(const std::string& name, const std::string& text) {
    const fs::path path = *dir_ / name;
    std::ofstream(path, std::ios::binary) << text;
    return path.string();
  }
  static CommandOutcome Cli(const std::string& args) {
    return RunCommand(std::string(MBSTREAM_CLI) + " " + args + " 2>&1 | head -c 4000");
  }
  static CommandOutcome Served(const std::string& args) {
    return RunCommand(std::string(MBSTREAM_CLI) + " --server " + server_->address() + " " + args);
  }
  static std::string Out() { return (*dir_ / "out").string(); }
  // The server still answers: a cheap call succeeds.
  static void ExpectServerAlive() {
    const CommandOutcome models = Served("models");
    EXPECT_EQ(models.exit_code, 0) << models.output;
    EXPECT_THAT(models.output, HasSubstr("irb1600"));
  }

  static fs::path* dir_;
  static ServerProcess* server_;
};

fs::path* HostileInputsTest::dir_ = nullptr;
ServerProcess* HostileInputsTest::server_ = nullptr;

TEST_F(HostileInputsTest, ModelsAreRefusedAlikeBySimulateAndTheServer) {
  for (const HostileModel& model : kModels) {
    SCOPED_TRACE(model.name);
    const std::string path = Write(std::string(model.name) + model.extension, model.text());
    // `| head` hides simulate's exit code: run it again for the code alone.
    const std::string simulate = "simulate " + path + " --out " + Out();
    const CommandOutcome local = RunCommand(std::string(MBSTREAM_CLI) + " " + simulate);
    EXPECT_EQ(local.exit_code, 2) << local.output.substr(0, 2000);
    EXPECT_THAT(local.output, HasSubstr(model.message));
    EXPECT_LT(local.output.size(), 2000u);
    const CommandOutcome served = Served("submit " + path);
    EXPECT_EQ(served.exit_code, 2) << served.output.substr(0, 2000);
    EXPECT_THAT(served.output, HasSubstr(model.message));
    ExpectServerAlive();
  }
}

TEST_F(HostileInputsTest, BytesThatAreNotUtf8AreNamedByFileAndLine) {
  const std::string path = Write("latin1.urdf", OneJointNamed("j\xFF"));
  const CommandOutcome local = Cli("simulate " + path + " --out " + Out());
  EXPECT_THAT(local.output, HasSubstr("latin1.urdf:4: byte 0xFF is not UTF-8"));
  const CommandOutcome served = Served("submit " + path);
  EXPECT_EQ(served.exit_code, 2);
  EXPECT_THAT(served.output, HasSubstr("latin1.urdf: line 4: byte 0xFF is not UTF-8"));
  EXPECT_THAT(served.output, Not(HasSubstr("libprotobuf")));
  std::string utf16 = "\xFF\xFE";
  for (char c : OneJointNamed("j")) utf16 += std::string(1, c) + '\0';
  const std::string wide = Write("utf16.urdf", utf16);
  EXPECT_THAT(Cli("simulate " + wide + " --out " + Out()).output, HasSubstr("UTF-16"));
  EXPECT_THAT(Served("submit " + wide).output, HasSubstr("UTF-16"));
  ExpectServerAlive();
}

TEST_F(HostileInputsTest, AModelWithoutMovingJointsAgrees) {
  const std::string path = Write("still.urdf", FixedChain(3));
  const std::string spec = Write("joint.json", R"({"duration_s": 1, "formulation": "joint"})");
  const CommandOutcome local = Cli("simulate " + path + " --spec " + spec + " --out " + Out());
  EXPECT_THAT(local.output, HasSubstr("formulation: joint integrates the motion of moving "
                                      "joints, and the model has none"));
  ASSERT_EQ(Served("submit " + path).exit_code, 0);
  const CommandOutcome served = Served("run chain --spec " + spec);
  EXPECT_EQ(served.exit_code, 2);
  EXPECT_THAT(served.output, HasSubstr("the model has none"));
  // Without a formulation both run it (auto: kinematic, nothing moves).
  const std::string plain = Write("plain.json", R"({"duration_s": 1})");
  EXPECT_EQ(RunCommand(std::string(MBSTREAM_CLI) + " simulate " + path + " --spec " + plain +
                       " --out " + Out())
                .exit_code,
            0);
}

struct HostileSpec {
  const char* name;
  std::string json;
  std::string message;  // in both answers
};

TEST_F(HostileInputsTest, SpecsAreRefusedAlikeBySimulateAndTheServer) {
  const HostileSpec specs[] = {
      {"tiny_max_step", R"({"duration_s": 1, "max_step_s": 5e-324})",
       "max_step_s: is 5e-324 s, below the smallest"},
      {"huge_gravity", R"({"duration_s": 1, "gravity": {"z": 1e300}})", "gravity.z: is 1e+300"},
      {"nested_initial_q", R"({"initial_q": [[0, 1], [2]]})", "initial_q[0] is a list inside"},
      {"null_initial_q", R"({"initial_q": [0, null, 0, 0, 0, 0]})", "initial_q[1] is null"},
      {"retries", R"({"retries": 1000})", "retries: is 1000"},
      {"nul_in_method", R"({"method": "bdf\u0000x"})", "method holds a NUL character"},
      {"long_duration", R"({"duration_s": 1e7})", "--max-duration"},
      {"tiny_interval", R"({"duration_s": 1, "output_interval_s": 1e-7})", "--max-output-frames"},
      {"spec_frame_cap", R"({"duration_s": 1, "max_output_frames": 5})",
       "spec.max_output_frames is 5"},
      {"huge_key", "{\"" + std::string(10 << 20, 'k') + "\": 1}", "has a key of 10485760 bytes"},
  };
  for (const HostileSpec& spec : specs) {
    SCOPED_TRACE(spec.name);
    const std::string path = Write(std::string(spec.name) + ".json", spec.json);
    const CommandOutcome local =
        RunCommand(std::string(MBSTREAM_CLI) + " simulate models/irb1600/irb1600.urdf --spec " +
                   path + " --out " + Out());
    EXPECT_EQ(local.exit_code, 2) << local.output.substr(0, 2000);
    EXPECT_THAT(local.output, HasSubstr(spec.message));
    EXPECT_LT(local.output.size(), 2000u);  // nothing echoed whole
    const CommandOutcome served = Served("run irb1600 --spec " + path);
    EXPECT_EQ(served.exit_code, 2) << served.output.substr(0, 2000);
    EXPECT_THAT(served.output, HasSubstr(spec.message));
  }
  ExpectServerAlive();
}

TEST_F(HostileInputsTest, SimulateSaysWhichSpecFieldsItIgnores) {
  const std::string path =
      Write("paced.json", R"({"duration_s": 0.1, "realtime": 1, "retries": 2})");
  const CommandOutcome local =
      Cli("simulate models/irb1600/irb1600.urdf --spec " + path + " --out " + Out());
  EXPECT_THAT(local.output, HasSubstr("spec.realtime is ignored"));
  EXPECT_THAT(local.output, HasSubstr("spec.retries is ignored"));
}

TEST_F(HostileInputsTest, SimulateLimitsAreFlagsLikeTheServers) {
  const std::string path = Write("ten_s.json", R"({"duration_s": 10})");
  const CommandOutcome refused = Cli("simulate models/irb1600/irb1600.urdf --spec " + path +
                                     " --max-duration 5 --out " + Out());
  EXPECT_THAT(refused.output, HasSubstr("exceeds the limit of 5 s (--max-duration)"));
  const std::string chain = Write("chain300.urdf", FixedChain(300));
  EXPECT_THAT(Cli("simulate " + chain + " --out " + Out()).output,
              HasSubstr("more than 256 <link> elements"));
  // Raised by the flag, the same inputs run.
  EXPECT_EQ(RunCommand(std::string(MBSTREAM_CLI) + " simulate " + chain +
                       " --max-links 400 --out " + Out())
                .exit_code,
            0);
}

}  // namespace
}  // namespace mbstream::testing
