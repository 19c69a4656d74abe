#include "tests/viewer/xvfb_display.h"

#include <gtest/gtest.h>

#include <cstdlib>

#include "tests/viewer/xvfb_server.h"

namespace mbstream::viewer::testing {

namespace {

class XvfbEnvironment : public ::testing::Environment {
 public:
  void SetUp() override { EnsureDisplay(); }
  void TearDown() override { server_.Stop(); }

  bool Start() {
    if (!server_.Start()) return false;
    setenv("DISPLAY", server_.display().c_str(), 1);
    return true;
  }

 private:
  XvfbServer server_;
};

XvfbEnvironment* const environment =
    static_cast<XvfbEnvironment*>(::testing::AddGlobalTestEnvironment(new XvfbEnvironment));

}  // namespace

bool EnsureDisplay() {
  const char* display = std::getenv("DISPLAY");
  if (display && *display) return true;
  return environment->Start();
}

}  // namespace mbstream::viewer::testing
