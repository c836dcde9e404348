#include "simulator/crowd.h"

#include <algorithm>
#include <cmath>

namespace navd::sim {

Point2 WalkingVelocity(const Person& p) {
  const Point2 to_goal = p.goal - p.position;
  return to_goal.norm() > 1e-9 ? Point2(p.speed * to_goal.normalized()) : Point2::Zero();
}

Crowd::Crowd(const CrowdDescription& description, uint64_t seed) : d_(description), rng_(seed) {}

Point2 Crowd::RandomPointInArea(double margin) {
  std::uniform_real_distribution<double> ux(d_.area.min.x() + margin,
                                            std::max(d_.area.min.x() + margin, d_.area.max.x() - margin));
  std::uniform_real_distribution<double> uy(d_.area.min.y() + margin,
                                            std::max(d_.area.min.y() + margin, d_.area.max.y() - margin));
  const double x = ux(rng_);
  return {x, uy(rng_)};
}

void Crowd::NewGoal(Person& p, double now) {
  if (d_.street) {
    // A goal goal_ahead metres further along the street, at a random place across it.
    std::uniform_real_distribution<double> uy(d_.area.min.y() + d_.radius, d_.area.max.y() - d_.radius);
    p.goal = {p.position.x() + p.direction * d_.goal_ahead, uy(rng_)};
  } else {
    p.goal = RandomPointInArea(d_.radius);
  }
  std::uniform_real_distribution<double> period(d_.goal_period_min, d_.goal_period_max);
  p.next_goal_change = now + period(rng_);
  p.last_goal_change = now;
  ++goal_changes_;
}

bool Crowd::Spawn(double now, bool at_street_end, const OccupancyQuery& occupied) {
  Person p;
  std::normal_distribution<double> speed(d_.speed_mean, d_.speed_std);
  p.speed = std::clamp(speed(rng_), 0.1, 2.5);  // people walk, they do not stand or sprint
  p.direction = std::bernoulli_distribution(0.5)(rng_) ? 1 : -1;
  p.position = RandomPointInArea(d_.radius);
  if (d_.street && at_street_end) {
    p.position.x() = p.direction > 0 ? d_.area.min.x() + d_.radius : d_.area.max.x() - d_.radius;
  }
  // Not inside a wall, another body, or too close to a robot.
  if (occupied(p.position, d_.radius, -1, false) != kFree ||
      occupied(p.position, d_.radius + d_.spawn_clearance, -1, true) != kFree) {
    return false;
  }
  p.id = next_id_++;
  NewGoal(p, now);
  --goal_changes_;  // the first goal is not a change
  people_.push_back(p);
  return true;
}

void Crowd::Populate(double now, const OccupancyQuery& occupied) {
  const int n = std::uniform_int_distribution<int>(d_.initial_min, std::max(d_.initial_min, d_.initial_max))(rng_);
  for (int placed = 0, tries = 0; placed < n && tries < 100 * (n + 1); ++tries) placed += Spawn(now, false, occupied);
  next_arrival_ = now + std::exponential_distribution<double>(d_.arrival_rate > 0 ? d_.arrival_rate : 1.0)(rng_);
}

void Crowd::Step(double now, double dt, const OccupancyQuery& occupied, const ContactReport& contact) {
  // Poisson arrivals: exponential gaps between them.
  while (d_.arrival_rate > 0 && now >= next_arrival_) {
    if (static_cast<int>(people_.size()) < d_.max_people) {
      for (int tries = 0; tries < 20; ++tries) {
        if (Spawn(now, true, occupied)) {
          ++arrivals_;
          break;
        }
      }
    }
    next_arrival_ += std::exponential_distribution<double>(d_.arrival_rate)(rng_);
  }
  std::normal_distribution<double> unit(0.0, 1.0);
  const double diffusion = d_.brownian * std::sqrt(dt);
  for (Person& p : people_) {
    const Point2 to_goal = p.goal - p.position;
    const double distance = to_goal.norm();
    if (now >= p.next_goal_change || (!d_.street && distance < 0.3)) NewGoal(p, now);
    Point2 step = distance > 1e-9 ? Point2(to_goal * std::min(p.speed * dt, distance) / distance) : Point2::Zero();
    step += diffusion * Point2(unit(rng_), unit(rng_));
    // Blocked by someone: step around them, first to one side (each person has a preferred side,
    // so two people meeting head-on pass instead of mirroring each other), then to the other.
    int hit = kFree;
    bool moved = false;
    const double side = (p.id % 2 == 0) ? 1.0 : -1.0;
    for (double turn : {0.0, side * M_PI / 4, -side * M_PI / 4, side * M_PI / 2, -side * M_PI / 2}) {
      const double c = std::cos(turn), sn = std::sin(turn);
      const Point2 next = p.position + Point2(c * step.x() - sn * step.y(), sn * step.x() + c * step.y());
      const int h = occupied(next, d_.radius, p.id, false);
      if (turn == 0.0) hit = h;
      if (h == kFree) {
        if (turn != 0.0 && hit >= kFirstPersonId) p.last_step_aside = now;
        p.velocity = (next - p.position) / dt;
        p.position = next;
        moved = true;
        break;
      }
      if (h == kWall) break;  // walls are not stepped around: pick a new goal instead
    }
    if (!moved) {
      p.velocity = Point2::Zero();
      if (hit == kWall) NewGoal(p, now);
    }
    if (hit >= 0 && hit < kFirstPersonId) contact(p, hit);
  }
  if (d_.street) {
    // People leave at the street's ends.
    const auto gone = std::remove_if(people_.begin(), people_.end(), [&](const Person& p) {
      return p.position.x() < d_.area.min.x() || p.position.x() > d_.area.max.x();
    });
    departures_ += static_cast<int>(people_.end() - gone);
    people_.erase(gone, people_.end());
  }
}

}  // namespace navd::sim
