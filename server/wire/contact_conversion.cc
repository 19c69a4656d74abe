#include "server/wire/contact_conversion.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "shared/common/check.h"

namespace mbstream {

namespace {

void SetVector(const double (&v)[3], v1::Vector3* out) {
  MBSTREAM_CHECK_MSG(std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]),
                     "a non-finite contact vector reached the wire");
  out->set_x(v[0]);
  out->set_y(v[1]);
  out->set_z(v[2]);
}

void GetVector(const v1::Vector3& v, double (&out)[3]) {
  out[0] = v.x();
  out[1] = v.y();
  out[2] = v.z();
}

}  // namespace

void ContactsToProto(const ContactLog& log, double t,
                     google::protobuf::RepeatedPtrField<v1::FrameContact>* out) {
  out->Clear();  // the elements stay allocated, and Add() reuses them
  if (log.active) {
    // The records are in frame order: the frame's are the run of those at t.
    const auto first =
        std::lower_bound(log.records.begin(), log.records.end(), t,
                         [](const ContactRecord& r, double time) { return r.t < time; });
    for (auto r = first; r != log.records.end() && r->t == t; ++r) {
      v1::FrameContact* c = out->Add();
      c->set_link_a(log.link[r->geometry_a]);
      c->set_collision_a(log.collision[r->geometry_a]);
      c->set_link_b(log.link[r->geometry_b]);
      c->set_collision_b(log.collision[r->geometry_b]);
      SetVector(r->point, c->mutable_point_m());
      SetVector(r->normal, c->mutable_normal());
      MBSTREAM_CHECK_MSG(std::isfinite(r->depth) && std::isfinite(r->normal_force),
                         "a non-finite contact force reached the wire");
      c->set_depth_m(r->depth);
      c->set_normal_force_n(r->normal_force);
      SetVector(r->friction, c->mutable_friction_force_n());
    }
  }
}

void ContactsFromFrames(const std::vector<v1::Frame>& frames, bool active, ContactLog* log) {
  *log = ContactLog();
  for (const v1::Frame& frame : frames) active = active || frame.contacts_size() > 0;
  if (!active) return;
  log->active = true;
  log->keep_records = true;
  const auto geometry = [&](const std::string& link, const std::string& collision) {
    for (size_t g = 0; g < log->link.size(); ++g) {
      if (log->link[g] == link && log->collision[g] == collision) return static_cast<int>(g);
    }
    log->link.push_back(link);
    log->collision.push_back(collision);
    log->size.push_back(INFINITY);  // not stored: only a live run's log needs it
    return static_cast<int>(log->link.size() - 1);
  };
  for (const v1::Frame& frame : frames) {
    int count = 0;
    for (const v1::FrameContact& c : frame.contacts()) {
      ContactRecord r;
      r.t = frame.t_s();
      r.geometry_a = geometry(c.link_a(), c.collision_a());
      r.geometry_b = geometry(c.link_b(), c.collision_b());
      GetVector(c.point_m(), r.point);
      GetVector(c.normal(), r.normal);
      r.depth = c.depth_m();
      r.normal_force = c.normal_force_n();
      GetVector(c.friction_force_n(), r.friction);
      log->depth_max = std::max(log->depth_max, r.depth);
      log->records.push_back(r);
      ++count;
    }
    log->count_peak = std::max(log->count_peak, count);
  }
}

}  // namespace mbstream
