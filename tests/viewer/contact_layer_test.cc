// The contacts' layer (viewer/scene/contact_layer.h): a point and a force arrow per contact,
// scaled as documented, no more than kMaxContacts, hidden when a frame has none.
#include "viewer/scene/contact_layer.h"

#include <gtest/gtest.h>

#include <vtkRenderer.h>

namespace mbstream::viewer {
namespace {

TEST(ContactLayerTest, ArrowsFollowTheForcesAtTheGivenScale) {
  auto renderer = vtkSmartPointer<vtkRenderer>::New();
  ContactLayer layer(renderer, 0.01);  // 1 cm per N
  const std::vector<ContactMark> marks = {{{0.1, 0.2, 0.0}, {0.0, 0.0, 5.0}},
                                          {{-0.1, 0.2, 0.0}, {1.0, -2.0, 4.0}}};
  layer.SetContacts(marks);
  layer.SyncActors();
  const std::vector<Eigen::Vector3d> tips = layer.ArrowTips();
  ASSERT_EQ(tips.size(), 2u);
  EXPECT_LT((tips[0] - Eigen::Vector3d(0.1, 0.2, 0.05)).norm(), 1e-15);
  EXPECT_LT((tips[1] - Eigen::Vector3d(-0.09, 0.18, 0.04)).norm(), 1e-15);
  EXPECT_TRUE(layer.points_actor()->GetVisibility());
  EXPECT_TRUE(layer.arrows_actor()->GetVisibility());
  EXPECT_EQ(layer.count(), 2);
  EXPECT_EQ(layer.frames_with_contacts(), 1);

  layer.SetContacts({});  // a frame without contacts hides both actors
  layer.SyncActors();
  EXPECT_FALSE(layer.points_actor()->GetVisibility());
  EXPECT_FALSE(layer.arrows_actor()->GetVisibility());
  EXPECT_TRUE(layer.ArrowTips().empty());
  EXPECT_EQ(layer.frames_with_contacts(), 1);
}

TEST(ContactLayerTest, AutomaticScaleDrawsTheLargestForceSoFarAQuarterMetreLong) {
  auto renderer = vtkSmartPointer<vtkRenderer>::New();
  ContactLayer layer(renderer, 0.0);
  const std::vector<ContactMark> first = {{{0, 0, 0}, {0, 0, 20.0}}, {{1, 0, 0}, {0, 0, 10.0}}};
  layer.SetContacts(first);
  layer.SyncActors();
  std::vector<Eigen::Vector3d> tips = layer.ArrowTips();
  EXPECT_NEAR(tips[0].z(), ContactLayer::kAutoLength, 1e-15);
  EXPECT_NEAR(tips[1].z(), 0.5 * ContactLayer::kAutoLength, 1e-15);
  // A smaller force later keeps the scale of the largest so far.
  const std::vector<ContactMark> later = {{{0, 0, 0}, {0, 0, 5.0}}};
  layer.SetContacts(later);
  layer.SyncActors();
  tips = layer.ArrowTips();
  ASSERT_EQ(tips.size(), 1u);
  EXPECT_NEAR(tips[0].z(), 0.25 * ContactLayer::kAutoLength, 1e-15);
}

TEST(ContactLayerTest, AFrameWithTooManyContactsDrawsTheFirstOnesOnly) {
  auto renderer = vtkSmartPointer<vtkRenderer>::New();
  ContactLayer layer(renderer, 1.0);
  std::vector<ContactMark> many(ContactLayer::kMaxContacts + 10);
  for (size_t i = 0; i < many.size(); ++i) many[i].point.x() = static_cast<double>(i);
  layer.SetContacts(many);
  layer.SyncActors();
  EXPECT_EQ(layer.count(), ContactLayer::kMaxContacts);
  std::vector<ContactMark> kept;
  layer.Marks(&kept);
  ASSERT_EQ(kept.size(), static_cast<size_t>(ContactLayer::kMaxContacts));
  EXPECT_EQ(kept.back().point.x(), ContactLayer::kMaxContacts - 1);
}

}  // namespace
}  // namespace mbstream::viewer
