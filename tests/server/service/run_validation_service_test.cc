// StartRun refuses at the door, with INVALID_ARGUMENT, every request that a worker would
// fail on for a reason knowable up front (ValidateRun), instead of queueing it to fail as
// "internal error:".
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "tests/server/service/server_fixture.h"

namespace mbstream {
namespace {

using ::testing::HasSubstr;

class RunValidationServiceTest : public testing::ServerTest {
 protected:
  void SetUp() override { StartServer(); }

  // A short free swing of the IRB 1600 with the given formulation, method and table.
  static v1::RunSpec Swing(const std::string& formulation, const std::string& method,
                           const std::string& table = "") {
    v1::RunSpec spec = SceneSpec("passive-swing.json");
    spec.set_duration_s(0.1);
    spec.set_formulation(formulation);
    spec.set_method(method);
    spec.set_erk_table(table);
    return spec;
  }
};

TEST_F(RunValidationServiceTest, RequestsTheWorkerWouldFailOnAreInvalidArguments) {
  struct Case {
    v1::RunSpec spec;
    const char* says;
  };
  const Case cases[] = {
      {Swing("joint", "ida"), "method ida"},
      {Swing("auto", "ida"), "method ida"},
      {Swing("joint", "erk", "nosuch"), "nosuch"},
      {Swing("joint", "dirk", "dormand-prince"), "dormand-prince"},
      {Swing("joint", "bdf", "dormand-prince"), "applies only to methods erk and dirk"},
      {Swing("body-index2", "ida", "sdirk"), "applies only to methods erk and dirk"},
      {Swing("body-baumgarte", "euler"), "method euler"},
      {Swing("body-index3", "bdf"), "needs method ida"},
  };
  for (const Case& c : cases) {
    v1::RunInfo info;
    const grpc::Status status = StartRun("irb1600", c.spec, &info);
    EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT)
        << c.spec.formulation() << " / " << c.spec.method() << ": " << status.error_message();
    EXPECT_THAT(status.error_message(), HasSubstr(c.says));
    EXPECT_THAT(status.error_message(), ::testing::Not(HasSubstr("internal error")));
  }
}

TEST_F(RunValidationServiceTest, AValidTableIsAccepted) {
  const v1::RunInfo started = StartRunOk("irb1600", Swing("joint", "erk", "heun-euler"));
  const v1::RunInfo ended = WaitForEnd(started.id());
  EXPECT_EQ(ended.state(), v1::FINISHED) << ended.message();
}

}  // namespace
}  // namespace mbstream
