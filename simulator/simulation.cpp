#include "simulator/simulation.h"

#include <algorithm>
#include <cmath>

#include "services/common/error.h"

namespace navd::sim {
namespace {

constexpr int kFirstObstacleId = 10000;

// Independent, reproducible streams per entity: adding a person does not change a robot's noise.
uint64_t StreamSeed(uint64_t seed, uint64_t stream) {
  uint64_t z = seed + 0x9E3779B97F4A7C15ull * (stream + 1);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

const std::vector<Person> kNobody;

}  // namespace

SimulatedRobot::SimulatedRobot(const RobotSpec& spec, int id, uint64_t seed)
    : spec_(spec),
      id_(id),
      sensor_rng_(StreamSeed(seed, 2 * id + 1)),
      people_rng_(StreamSeed(seed, (1u << 21) + id)),
      camera_rng_(StreamSeed(seed, (1u << 22) + id)),
      base_(spec.body, spec.start, StreamSeed(seed, 2 * id)) {
  if (spec.laser) laser_.emplace(*spec.laser);
  if (spec.sonar) sonar_.emplace(*spec.sonar);
  if (spec.ir) ir_.emplace(*spec.ir);
  if (spec.camera) camera_.emplace(*spec.camera);
}

Simulation::Simulation(World world, const SimulationOptions& options)
    : Simulation(ScenarioFromWorld(std::move(world)), options) {}

Simulation::Simulation(Scenario scenario, const SimulationOptions& options)
    : scenario_(std::move(scenario)),
      options_(options),
      seed_(options.seed.value_or(scenario_.seed)),
      truth_(scenario_.truth) {
  RebuildViews();
  for (size_t i = 0; i < scenario_.robots.size(); ++i) {
    robots_.push_back(std::make_unique<SimulatedRobot>(scenario_.robots[i], static_cast<int>(i), seed_));
  }
  for (const auto& d : scenario_.moving_obstacles) obstacles_.emplace_back(d);
  if (scenario_.crowd) {
    crowd_ = std::make_unique<Crowd>(*scenario_.crowd, StreamSeed(seed_, 1u << 20));
    crowd_->Populate(now_, [this](const Point2& c, double r, int self, bool robots_only) {
      return Occupied(c, r, self, robots_only);
    });
  }
}

void Simulation::SetCameraWatched(size_t index, bool watched) { robots_.at(index)->camera_watched_ = watched; }

void Simulation::RebuildViews() {
  laser_truth_.reset();
  camera_walls_.reset();
  if (!scenario_.see_through.empty()) laser_truth_.emplace(WithCellsFree(scenario_.truth, scenario_.see_through));
  if (!scenario_.solid_cells.empty()) camera_walls_.emplace(WithCellsFree(scenario_.truth, scenario_.solid_cells));
}

void Simulation::SetDoor(const std::string& name, bool closed) {
  auto door =
      std::find_if(scenario_.doors.begin(), scenario_.doors.end(), [&](const Door& d) { return d.name == name; });
  if (door == scenario_.doors.end()) {
    std::string known;
    for (const Door& d : scenario_.doors) known += (known.empty() ? "" : ", ") + d.name;
    throw Error(ErrorCode::kNotFound, "no door '" + name + "' (doors: " + (known.empty() ? "none" : known) + ")");
  }
  if (door->closed == closed) return;
  door->closed = closed;
  OccupancyGrid truth = TruthWithDoors(scenario_.fixed_truth, scenario_.doors);
  if (closed) {
    // Bodies never overlap the walls they have, so a body the new truth overlaps stands in the door.
    for (const Disc& d : Discs()) {
      if (truth.DiscHitsObstacle(d.centre, d.radius) && !scenario_.truth.DiscHitsObstacle(d.centre, d.radius)) {
        door->closed = false;
        throw Error(ErrorCode::kFailedPrecondition, "door '" + name + "' cannot close on " + BodyName(d.id));
      }
    }
  }
  scenario_.truth = std::move(truth);
  truth_ = RayCaster(scenario_.truth);
  RebuildViews();
}

const std::vector<Person>& Simulation::people() const { return crowd_ ? crowd_->people() : kNobody; }

std::vector<Disc> Simulation::Discs() const {
  std::vector<Disc> out;
  out.reserve(robots_.size() + obstacles_.size() + people().size());
  for (const auto& r : robots_) out.push_back({r->base().true_pose().translation(), r->spec().body.radius, r->id()});
  for (size_t i = 0; i < obstacles_.size(); ++i) {
    out.push_back(
        {obstacles_[i].position(), obstacles_[i].description().radius, kFirstObstacleId + static_cast<int>(i)});
  }
  for (const auto& p : people()) out.push_back({p.position, scenario_.crowd->radius, p.id});
  return out;
}

std::string Simulation::BodyName(int id) const {
  if (id == kWall) return "wall";
  if (id >= Crowd::kFirstPersonId) return "person " + std::to_string(id);
  if (id >= kFirstObstacleId) return obstacles_.at(id - kFirstObstacleId).description().name;
  const std::string& name = robots_.at(id)->name();
  return name.empty() ? "robot" : name;
}

std::optional<std::pair<Point2, Point2>> Simulation::BodyMotion(int id) const {
  if (id >= Crowd::kFirstPersonId) {
    if (crowd_)
      for (const auto& p : crowd_->people())
        if (p.id == id) return std::pair{p.position, WalkingVelocity(p)};
    return std::nullopt;
  }
  if (id >= kFirstObstacleId) {
    if (id - kFirstObstacleId >= static_cast<int>(obstacles_.size())) return std::nullopt;
    const MovingObstacle& o = obstacles_[static_cast<size_t>(id - kFirstObstacleId)];
    return std::pair{o.position(), o.velocity()};
  }
  if (id < 0 || id >= static_cast<int>(robots_.size())) return std::nullopt;
  const auto& base = robots_[static_cast<size_t>(id)]->base();
  const Pose2& pose = base.true_pose();
  const BodyTwist t = base.true_twist();
  return std::pair{pose.translation(), Pose2{0.0, 0.0, pose.theta} * Point2(t.vx, t.vy)};
}

int Simulation::Occupied(const Point2& centre, double radius, int self, bool robots_only) const {
  if (!robots_only && truth_.DiscHitsWall(centre, radius)) return kWall;
  auto overlaps = [&](const Point2& c, double r) { return (c - centre).squaredNorm() < (r + radius) * (r + radius); };
  for (const auto& r : robots_) {
    if (r->id() != self && overlaps(r->base().true_pose().translation(), r->spec().body.radius)) return r->id();
  }
  if (robots_only) return kFree;
  for (size_t i = 0; i < obstacles_.size(); ++i) {
    const int id = kFirstObstacleId + static_cast<int>(i);
    if (id != self && overlaps(obstacles_[i].position(), obstacles_[i].description().radius)) return id;
  }
  if (crowd_) {
    for (const auto& p : crowd_->people()) {
      if (p.id != self && overlaps(p.position, crowd_->description().radius)) return p.id;
    }
  }
  return kFree;
}

void Simulation::Command(size_t index, const BodyTwist& twist) {
  if (!std::isfinite(twist.vx) || !std::isfinite(twist.vy) || !std::isfinite(twist.omega)) return;  // never act on NaN
  auto& r = *robots_.at(index);
  r.base_.CommandVelocity(twist);
  r.last_command_ = now_;
  r.watchdog_stopped_ = false;
}

void Simulation::CommandAcceleration(size_t index, double linear, double angular) {
  if (!std::isfinite(linear) || !std::isfinite(angular)) return;
  auto& r = *robots_.at(index);
  r.base_.CommandAcceleration(linear, angular);
  r.last_command_ = now_;
  r.watchdog_stopped_ = false;
}

std::vector<PersonReading> Simulation::SensePeople(SimulatedRobot& r) {
  const PeopleSensorDescription& d = *r.spec_.people;
  const Pose2 to_robot = r.base_.true_pose().inverse();
  std::normal_distribution<double> unit(0.0, 1.0);
  std::vector<PersonReading> seen;
  for (const Person& p : people()) {
    const Point2 at = to_robot * p.position;
    if (at.norm() > d.range_max || std::abs(std::atan2(at.y(), at.x())) > 0.5 * d.fov) continue;
    // The velocity they walk with (a tracker's smoothed one, not the Brownian step's); none while
    // something stops them (a walker waiting at the robot's rim does not walk into it).
    const Point2 v = p.velocity.isZero() ? Point2::Zero() : WalkingVelocity(p);
    PersonReading reading{p.id, at, Rotate(v, to_robot.theta)};
    if (d.position_noise > 0.0) reading.position += d.position_noise * Point2(unit(r.people_rng_), unit(r.people_rng_));
    if (d.velocity_noise > 0.0) reading.velocity += d.velocity_noise * Point2(unit(r.people_rng_), unit(r.people_rng_));
    seen.push_back(reading);
  }
  return seen;
}

bool Simulation::Due(double rate, double& last) const {
  const double period = 1.0 / rate;
  // A small tolerance keeps float steps from skipping a sample.
  if (now_ - last < period - 1e-9) return false;
  last = last < 0 ? now_ : last + period;
  if (now_ - last >= period) last = now_;  // fell behind: resynchronise, do not burst
  return true;
}

void Simulation::Touch(SimulatedRobot& robot, int other, const Point2& where, bool robot_moved, double robot_closing,
                       double other_closing) {
  // A collision is the robot's own motion into something. People and obstacles that walk up to a
  // robot stop short of it (they press its bumper, but that is not the robot's collision).
  if (robot_moved) {
    if (!robot.contact_this_step_) {
      robot.contact_with_ = BodyName(other);
      robot.contact_other_id_ = other;
      robot.contact_where_ = where;
      robot.contact_robot_closing_ = robot_closing;
      robot.contact_other_closing_ = other_closing;
    }
    robot.contact_this_step_ = true;
  }
  // Which bumper: the side of the robot the contact is on.
  const Pose2& pose = robot.base().true_pose();
  const Point2 local = pose.inverse() * where;
  (local.x() >= 0 ? robot.bumper_.front : robot.bumper_.rear) = true;
}

StepOutputs Simulation::Step() {
  const double dt = options_.physics_step;
  MoveRobots(dt);
  MoveObstacles(dt);
  if (crowd_) {
    crowd_->Step(
        now_, dt,
        [this](const Point2& c, double r, int self, bool robots_only) { return Occupied(c, r, self, robots_only); },
        [this](const Person& p, int body) {
          if (body < kFirstObstacleId) Touch(*robots_[body], p.id, p.position, false);
        });
  }
  now_ += dt;
  StepOutputs out;
  out.events = CountCollisions();
  out.robots = ReadSensors();
  out.truth = Due(options_.truth_rate, last_truth_);
  out.status = Due(options_.status_rate, last_status_);
  return out;
}

void Simulation::MoveRobots(double dt) {
  for (auto& r : robots_) {
    r->contact_this_step_ = false;
    r->bumper_ = {};
  }
  // Robots move one after another against the others' current positions.
  for (auto& r : robots_) {
    if (!r->watchdog_stopped_ && now_ - r->last_command_ > options_.command_timeout) {
      r->base_.Stop();
      r->watchdog_stopped_ = true;
    }
    const Pose2 from = r->base_.true_pose();
    const Pose2 next = r->base_.ProposeMotion(dt);
    const bool moving = Distance(next.translation(), from.translation()) > 0.0;
    const int hit = moving ? Occupied(next.translation(), r->spec_.body.radius, r->id_, false) : kFree;
    r->base_.CommitMotion(hit != kFree, dt);
    if (hit != kFree) {
      // Where it touched: just beyond the rim in the direction it tried to go.
      const Point2 step = next.translation() - from.translation();
      const Point2 dir = step.normalized();
      // Who closed the gap, along the line between the centres (for a wall, the way it went).
      Point2 towards = dir;
      double other_closing = 0.0;
      if (const auto motion = hit != kWall ? BodyMotion(hit) : std::nullopt) {
        const auto& [centre, velocity] = *motion;
        if ((centre - from.translation()).norm() > 1e-9) towards = (centre - from.translation()).normalized();
        other_closing = -velocity.dot(towards);
      }
      Touch(*r, hit, from.translation() + r->spec_.body.radius * dir, true, step.dot(towards) / dt, other_closing);
    }
  }
}

void Simulation::MoveObstacles(double dt) {
  // Scripted obstacles wait while a body is in the way.
  for (size_t i = 0; i < obstacles_.size(); ++i) {
    auto& o = obstacles_[i];
    const int id = kFirstObstacleId + static_cast<int>(i);
    const Point2 next = o.Peek(dt);
    const int hit = Occupied(next, o.description().radius, id, false);
    if (hit == kFree || hit == kWall) {
      o.Advance(dt);  // loops were checked clear of walls; grazing corners must not stall them
    } else {
      o.Hold(dt);
      if (hit < kFirstObstacleId) Touch(*robots_[hit], id, next, false);
    }
  }
}

std::vector<CollisionEvent> Simulation::CountCollisions() {
  std::vector<CollisionEvent> events;
  // One contact is one collision, however often a stalled robot nudges again: it ends only after
  // kContactGap without touching.
  constexpr double kContactGap = 0.25;
  for (auto& r : robots_) {
    if (r->contact_this_step_) {
      if (now_ - r->last_contact_ > kContactGap) {
        ++r->collisions_;
        events.push_back({now_, r->name().empty() ? "robot" : r->name(), r->contact_with_, r->contact_other_id_,
                          r->contact_where_, r->contact_robot_closing_, r->contact_other_closing_});
      }
      r->last_contact_ = now_;
    }
    r->in_contact_ = now_ - r->last_contact_ <= kContactGap;
  }
  return events;
}

std::vector<RobotReadings> Simulation::ReadSensors() {
  const bool any_sensor_due = [&] {
    for (const auto& r : robots_) {
      if ((r->laser_ && now_ - r->last_scan_ >= 1.0 / r->laser_->description().rate - 1e-9) ||
          (r->sonar_ && now_ - r->last_sonar_ >= 1.0 / r->sonar_->description().rate - 1e-9) ||
          (r->ir_ && now_ - r->last_ir_ >= 1.0 / r->ir_->description().rate - 1e-9) ||
          (r->camera_ && now_ - r->last_camera_ >= 1.0 / r->camera_->description().rate - 1e-9)) {
        return true;
      }
    }
    return false;
  }();
  const std::vector<Disc> discs = any_sensor_due ? Discs() : std::vector<Disc>();
  std::vector<RobotReadings> readings(robots_.size());
  for (size_t i = 0; i < robots_.size(); ++i) {
    auto& r = *robots_[i];
    auto& o = readings[i];
    const Pose2& pose = r.base_.true_pose();
    if (r.laser_ && Due(r.laser_->description().rate, r.last_scan_)) {
      o.scan = r.laser_->Scan(pose, laser_truth(), discs, r.id_, r.sensor_rng_);
    }
    if (r.sonar_ && Due(r.sonar_->description().rate, r.last_sonar_)) {
      o.sonar = r.sonar_->Read(pose, truth_, discs, r.id_, r.sensor_rng_);
    }
    if (r.ir_ && Due(r.ir_->description().rate, r.last_ir_))
      o.ir = r.ir_->Read(pose, truth_, discs, r.id_, r.sensor_rng_);
    if (r.camera_ && Due(r.camera_->description().rate, r.last_camera_) && r.camera_watched_)
      o.camera = r.camera_->Capture(pose, camera_walls(), scenario_.solids, discs, r.id_, r.camera_rng_);
    o.odom = Due(options_.odom_rate, r.last_odom_);
    o.encoders = r.spec_.encoders && Due(r.spec_.encoder_rate, r.last_encoders_);
    o.bumper = r.spec_.bumper && Due(r.spec_.bumper_rate, r.last_bumper_);
    if (r.spec_.people && Due(r.spec_.people->rate, r.last_people_)) o.people = SensePeople(r);
  }
  return readings;
}

}  // namespace navd::sim
