// The run spec's contact section (proto/mbstream/v1/run_spec.proto) through JSON to
// RunConfig::contact and back; non-finite values refused at the edge with the field's name.
#include <gtest/gtest.h>

#include <string>

#include "server/spec/run_spec_json.h"
#include "shared/common/check.h"

namespace mbstream {
namespace {

RunConfig FromJson(const std::string& json) {
  return ToRunConfig(ParseRunSpecJson(json, "spec.json"), std::vector<std::string>{}, "spec.json");
}

TEST(ContactSpecTest, JsonSectionReachesTheRunConfigAndRoundTrips) {
  const RunConfig config = FromJson(R"({"contact": {"enabled": true, "stiffness_n_per_m": 2e6,
      "dissipation_s_per_m": 0.5, "mu_static": 0.9, "mu_dynamic": 0.7,
      "stiction_tolerance_m_per_s": 1e-3, "hertz_modulus_pa": 1e7,
      "collision_filter": [{"a": "left_finger", "b": "right_finger"}]}})");
  const ContactSettings& c = config.contact;
  EXPECT_TRUE(c.enabled);
  EXPECT_EQ(c.stiffness, 2e6);
  EXPECT_EQ(c.dissipation, 0.5);
  EXPECT_EQ(c.mu_static, 0.9);
  EXPECT_EQ(c.mu_dynamic, 0.7);
  EXPECT_EQ(c.stiction_tolerance, 1e-3);
  EXPECT_EQ(c.hertz_modulus, 1e7);
  ASSERT_EQ(c.filter.size(), 1u);
  EXPECT_EQ(c.filter[0].first, "left_finger");
  EXPECT_EQ(c.filter[0].second, "right_finger");
  const RunConfig back = ToRunConfig(ToRunSpec(config), std::vector<std::string>{}, "round trip");
  EXPECT_EQ(back.contact, config.contact);
}

TEST(ContactSpecTest, AbsentSectionIsOnWithTheDefaults) {
  const RunConfig config = FromJson("{}");
  EXPECT_EQ(config.contact, ContactSettings{});
  EXPECT_FALSE(FromJson(R"({"contact": {"enabled": false}})").contact.enabled);
}

TEST(ContactSpecTest, NonFiniteValuesAndEmptyNamesAreRefusedByField) {
  auto refused = [](const std::string& json, const std::string& field) {
    try {
      FromJson(json);
      ADD_FAILURE() << json << " accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
    }
  };
  refused(R"({"contact": {"stiffness_n_per_m": "Infinity"}})", "contact.stiffness_n_per_m");
  refused(R"({"contact": {"mu_static": "NaN"}})", "contact.mu_static");
  refused(R"({"contact": {"hertz_modulus_pa": "-Infinity"}})", "contact.hertz_modulus_pa");
  refused(R"({"contact": {"collision_filter": [{"a": "x"}]}})", "contact.collision_filter[0].b");
  refused(R"({"contact": {"stiffnes": 1}})", "stiffnes");
}

}  // namespace
}  // namespace mbstream
