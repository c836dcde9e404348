#include "simulator/truth_view.h"

#include "view/foxglove_messages.h"

namespace navd::sim {

TruthView::TruthView(view::FoxgloveServerOptions options, const Simulation& simulation, double rate)
    : server_(std::move(options)),
      period_(
          std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(1.0 / rate))),
      next_(std::chrono::steady_clock::now()) {
  map_ = server_.Advertise({"/map", "json", "foxglove.Grid", view::kGridSchema});
  robots_ = server_.Advertise({"/truth/robots", "json", "navd.MovingDiscs", view::kMovingDiscsSchema});
  people_ = server_.Advertise({"/truth/people", "json", "navd.MovingDiscs", view::kMovingDiscsSchema});
  obstacles_ = server_.Advertise({"/truth/obstacles", "json", "navd.MovingDiscs", view::kMovingDiscsSchema});
  // The world's map, as the robots' navd serve it; a subscriber gets it whenever it joins.
  server_.Publish(map_, 0, view::OccupancyGridJson(simulation.world().map, simulation.now(), "map"));
  server_.Start();
}

void TruthView::Update(const Simulation& s) {
  const auto now = std::chrono::steady_clock::now();
  if (now < next_) return;
  next_ = now + period_;
  const double t = s.now();
  const uint64_t stamp = view::StampNanoseconds(t);
  if (server_.HasSubscribers(robots_)) {
    std::vector<view::MovingDisc> discs;
    for (const auto& r : s.robots()) {
      const Pose2& p = r->base().true_pose();
      const auto tw = r->base().true_twist();
      discs.push_back({s.BodyName(r->id()), p.translation(), Rotate(Point2(tw.vx, tw.vy), p.theta),
                       r->spec().body.radius, "robot"});
    }
    server_.Publish(robots_, stamp, view::MovingDiscsJson(discs, t, "map"));
  }
  if (server_.HasSubscribers(people_)) {
    std::vector<view::MovingDisc> discs;
    const double radius = s.scenario().crowd ? s.scenario().crowd->radius : 0.25;
    for (const auto& p : s.people()) {
      discs.push_back({"person " + std::to_string(p.id), p.position, p.velocity, radius, "person"});
    }
    server_.Publish(people_, stamp, view::MovingDiscsJson(discs, t, "map"));
  }
  if (server_.HasSubscribers(obstacles_)) {
    std::vector<view::MovingDisc> discs;
    for (const auto& o : s.moving_obstacles()) {
      discs.push_back({o.description().name, o.position(), o.velocity(), o.description().radius, "obstacle"});
    }
    server_.Publish(obstacles_, stamp, view::MovingDiscsJson(discs, t, "map"));
  }
}

}  // namespace navd::sim
