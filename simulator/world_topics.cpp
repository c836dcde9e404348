#include "simulator/world_topics.h"

#include <spdlog/spdlog.h>

#include <cmath>

#include "dds/conversions.h"
#include "dds/topics.h"
#include "services/common/error.h"

namespace navd::sim {
namespace {

namespace msgs_sim = navsim_msgs::msg::dds_;
using dds::MakeHeader;
using dds::Reliability;

msgs_sim::WorldState_ MakeWorldState(double t, const Simulation& s) {
  msgs_sim::WorldState_ w;
  w.header(MakeHeader(t, "map"));
  auto add = [&](const std::string& name, const char* kind, const Pose2& pose, const Point2& v, double radius) {
    msgs_sim::Body_ b;
    b.name(name);
    b.kind(kind);
    b.x(pose.x);
    b.y(pose.y);
    b.theta(pose.theta);
    b.vx(v.x());
    b.vy(v.y());
    b.radius(radius);
    w.bodies().push_back(b);
  };
  for (const auto& r : s.robots()) {
    const Pose2& p = r->base().true_pose();
    const auto tw = r->base().true_twist();
    const double c = std::cos(p.theta), sn = std::sin(p.theta);
    add(s.BodyName(r->id()), "robot", p, {c * tw.vx - sn * tw.vy, sn * tw.vx + c * tw.vy}, r->spec().body.radius);
  }
  for (const auto& o : s.moving_obstacles()) {
    add(o.description().name, "obstacle",
        {o.position().x(), o.position().y(), std::atan2(o.velocity().y(), o.velocity().x())}, o.velocity(),
        o.description().radius);
  }
  for (const auto& p : s.people()) {
    add("person " + std::to_string(p.id), "person",
        {p.position.x(), p.position.y(), std::atan2(p.velocity.y(), p.velocity.x())}, p.velocity,
        s.scenario().crowd->radius);
  }
  for (const auto& d : s.scenario().doors) {
    msgs_sim::DoorState_ door;
    door.name(d.name);
    door.closed(d.closed);
    w.doors().push_back(door);
  }
  return w;
}

}  // namespace

WorldTopics::WorldTopics(dds::Participant& p)
    : clock_(p, dds::kClock, Reliability::kBestEffort, 1),
      world_(p, dds::kWorldState, Reliability::kBestEffort, 2),
      collisions_(p, dds::kCollisions, Reliability::kReliable, 100),
      door_commands_(p, dds::kDoorCommand, Reliability::kReliable, [this](const msgs_sim::DoorCommand_& m) {
        std::lock_guard<std::mutex> lock(mutex_);
        pending_doors_.emplace_back(m.name(), m.closed());
      }) {}

void WorldTopics::PublishClock(double t) {
  rosgraph_msgs::msg::dds_::Clock_ clock;
  clock.clock(dds::ToTime(t));
  clock_.Write(clock);
}

void WorldTopics::PublishWorldState(double t, const Simulation& simulation) {
  world_.Write(MakeWorldState(t, simulation));
}

void WorldTopics::PublishCollision(const CollisionEvent& e) {
  msgs_sim::CollisionEvent_ m;
  m.header(MakeHeader(e.time, "map"));
  m.robot(e.robot);
  m.other(e.other);
  m.x(e.where.x());
  m.y(e.where.y());
  collisions_.Write(m);
}

void WorldTopics::ApplyDoorCommands(Simulation& simulation) {
  std::vector<std::pair<std::string, bool>> pending;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    pending.swap(pending_doors_);
  }
  for (const auto& [name, closed] : pending) {
    try {
      simulation.SetDoor(name, closed);
      spdlog::info("navsim: door '{}' {} at t={:.2f}s", name, closed ? "closed" : "opened", simulation.now());
    } catch (const Error& e) {
      spdlog::warn("navsim: ignored {} command: {}", dds::kDoorCommand, e.what());
    }
  }
}

}  // namespace navd::sim
