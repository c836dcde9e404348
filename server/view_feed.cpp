#include "server/view_feed.h"

#include <spdlog/spdlog.h>

#include <chrono>
#include <cmath>
#include <nlohmann/json.hpp>

#include "services/common/error.h"
#include "view/foxglove_messages.h"

namespace navd::server {
namespace {

using Json = nlohmann::json;
constexpr const char* kMapFrame = "map";
constexpr uint8_t kLethalCost = 254;  // Nav2's inscribed-inflated value, above every decaying cost

const char* const kStatusSchema =
    R"({"title":"navd.Status","type":"object","properties":{"stamp":{"type":"number"},)"
    R"("state":{"type":"string"},"behaviour":{"type":"string"},"hold_reason":{"type":"string"},)"
    R"("active":{"type":"boolean"},"paused":{"type":"boolean"},"sensors_stale":{"type":"boolean"},)"
    R"("localizer":{"type":"string"},"localization_quality":{"type":"number"},)"
    R"("localization_lost":{"type":"boolean"},"localization_losses":{"type":"integer"},)"
    R"("danger":{"type":"number"},"speed_limit":{"type":"number"},"reflex":{"type":"string"},)"
    R"("utilities":{"type":"array","items":{"type":"object","properties":{"name":{"type":"string"},)"
    R"("utility":{"type":"number"},"gamma":{"type":"number"},"active":{"type":"boolean"}}}}},)"
    R"("required":["stamp","state","behaviour","active"]})";

const char* const kMissionSchema =
    R"({"title":"navd.Mission","type":"object","properties":{"stamp":{"type":"number"},)"
    R"("goal_id":{"type":"integer"},"active":{"type":"boolean"},)"
    R"("goal":{"type":"object","properties":{"x":{"type":"number"},"y":{"type":"number"},"yaw":{"type":"number"}}},)"
    R"("waypoints":{"type":"array","items":{"type":"object","properties":{"x":{"type":"number"},"y":{"type":"number"}}}},)"
    R"("mission_index":{"type":"integer"},"mission_count":{"type":"integer"},"laps_completed":{"type":"integer"},)"
    R"("waypoints_reached":{"type":"integer"},"distance_remaining":{"type":"number"},)"
    R"("distance_travelled":{"type":"number"},"eta":{"type":"number"},"recoveries":{"type":"integer"},)"
    R"("last_result":{"type":"object","properties":{"goal_id":{"type":"integer"},"outcome":{"type":"string"},)"
    R"("message":{"type":"string"}}}},"required":["stamp","goal_id","active"]})";

double Finite(double v) { return std::isfinite(v) ? v : 0.0; }

// The costmap as Nav2's costs (0-253, lethal 254) per cell, row-major like its grid.
std::vector<uint8_t> CostmapCells(const planning::Costmap& costmap) {
  const OccupancyGrid& grid = costmap.grid();
  std::vector<uint8_t> cost(grid.cells().size());
  for (int y = 0; y < grid.height(); ++y) {
    for (int x = 0; x < grid.width(); ++x) {
      const CellIndex c{x, y};
      cost[grid.Flat(c)] = costmap.IsLethal(c) ? kLethalCost : costmap.cost(c);
    }
  }
  return cost;
}

// /status: what the executive does and why, and how sure the localiser is.
Json StatusJson(double now, const navigation::NavigationStatus& s, const std::string& localizer,
                const localization::PoseEstimate& estimate, const navigation::NavigationExecutive& executive) {
  Json utilities = Json::array();
  for (const navigation::ProcessUtility& u : s.feedback.utilities) {
    utilities.push_back(
        {{"name", u.name}, {"utility", Finite(u.utility)}, {"gamma", Finite(u.gamma)}, {"active", u.active}});
  }
  return {{"stamp", now},
          {"state", navigation::NavigationStateName(s.feedback.state)},
          {"behaviour", s.feedback.behaviour},
          {"hold_reason", s.hold_reason},
          {"active", s.active},
          {"paused", s.paused},
          {"sensors_stale", s.sensors_stale},
          {"localizer", localizer},
          {"localization_quality", Finite(estimate.quality)},
          {"localization_lost", executive.localization_lost()},
          {"localization_losses", executive.localization_losses()},
          {"danger", Finite(s.feedback.danger)},
          {"speed_limit", Finite(s.feedback.speed_limit)},
          {"reflex", s.feedback.reflex},
          {"utilities", utilities}};
}

// /mission: the goal, the waypoints and the progress through them, and how the last one ended.
Json MissionJson(double now, const navigation::NavigationStatus& s, const navigation::Navigator& navigator) {
  Json waypoints = Json::array();
  for (const navigation::NavigationGoal& g : navigator.MissionWaypoints()) {
    waypoints.push_back({{"x", g.pose.x}, {"y", g.pose.y}});
  }
  Json mission = {{"stamp", now},
                  {"goal_id", s.goal_id},
                  {"active", s.active},
                  {"goal", {{"x", s.goal.pose.x}, {"y", s.goal.pose.y}, {"yaw", s.goal.pose.theta}}},
                  {"waypoints", waypoints},
                  {"mission_index", s.feedback.mission_index},
                  {"mission_count", s.feedback.mission_count},
                  {"laps_completed", s.feedback.laps_completed},
                  {"waypoints_reached", s.feedback.waypoints_reached},
                  {"distance_remaining", Finite(s.feedback.distance_remaining)},
                  {"distance_travelled", Finite(s.feedback.distance_travelled)},
                  {"eta", Finite(s.feedback.eta)},
                  {"recoveries", s.feedback.recoveries}};
  if (s.last_result) {
    mission["last_result"] = {{"outcome", navigation::OutcomeName(s.last_result->outcome)},
                              {"message", s.last_result->message}};
  }
  return mission;
}

// The goal of a "/goal" message: {x, y[, yaw]} or {pose: {position: {x, y}, orientation: {z, w}}}
// (map frame). Throws navd::Error naming the field that is missing or not a number.
navigation::NavigateRequest ParseGoal(const std::string& payload) {
  Json m;
  try {
    m = Json::parse(payload);
  } catch (const Json::exception&) {
    throw Error(ErrorCode::kInvalidArgument, "goal: not a JSON object");
  }
  auto number = [](const Json& j, const char* key, const std::string& field) {
    if (!j.is_object() || !j.contains(key) || !j[key].is_number()) {
      throw Error(ErrorCode::kInvalidArgument, "goal: " + field + " is missing or not a number");
    }
    const double v = j[key].get<double>();
    if (!std::isfinite(v)) throw Error(ErrorCode::kInvalidArgument, "goal: " + field + " is not a finite number");
    return v;
  };
  navigation::NavigateRequest r;
  r.preempt = true;  // a click on the map replaces the goal being driven to
  if (m.is_object() && m.contains("pose")) {
    const Json& pose = m["pose"];
    const Json position = pose.is_object() ? pose.value("position", Json()) : Json();
    r.goal.x = number(position, "x", "pose.position.x");
    r.goal.y = number(position, "y", "pose.position.y");
    if (pose.contains("orientation")) {
      const Json& q = pose["orientation"];
      r.goal.theta = 2.0 * std::atan2(number(q, "z", "pose.orientation.z"), number(q, "w", "pose.orientation.w"));
      r.use_goal_heading = true;
    }
  } else {
    r.goal.x = number(m, "x", "x");
    r.goal.y = number(m, "y", "y");
    if (m.is_object() && m.contains("yaw")) {
      r.goal.theta = number(m, "yaw", "yaw");
      r.use_goal_heading = true;
    }
  }
  return r;
}

}  // namespace

ViewFeed::ViewFeed(ViewFeedOptions options, ViewSources sources)
    : options_(std::move(options)), sources_(sources), server_(options_.server) {
  using view::ChannelSpec;
  channels_.map = server_.Advertise({"/map", "json", "foxglove.Grid", view::kGridSchema});
  channels_.map_building = server_.Advertise({"/map_building", "json", "foxglove.Grid", view::kGridSchema});
  channels_.costmap = server_.Advertise({"/costmap", "json", "foxglove.Grid", view::kGridSchema});
  channels_.pose = server_.Advertise({"/pose", "json", "foxglove.PoseInFrame", view::kPoseSchema});
  channels_.transform = server_.Advertise({"/tf", "json", "foxglove.FrameTransform", view::kFrameTransformSchema});
  channels_.path = server_.Advertise({"/path", "json", "foxglove.PosesInFrame", view::kPathSchema});
  channels_.path_ahead = server_.Advertise({"/path_ahead", "json", "foxglove.PosesInFrame", view::kPathSchema});
  channels_.scan = server_.Advertise({"/scan", "json", "foxglove.LaserScan", view::kLaserScanSchema});
  channels_.people = server_.Advertise({"/people", "json", "navd.MovingDiscs", view::kMovingDiscsSchema});
  channels_.obstacles = server_.Advertise({"/moving_obstacles", "json", "navd.MovingDiscs", view::kMovingDiscsSchema});
  channels_.status = server_.Advertise({"/status", "json", "navd.Status", kStatusSchema});
  channels_.mission = server_.Advertise({"/mission", "json", "navd.Mission", kMissionSchema});
  server_.OnClientMessage([this](const view::ClientMessage& m) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (commands_.size() >= 16) commands_.pop_front();  // a flood keeps only the newest requests
      commands_.push_back(m);
    }
    wake_.notify_all();
  });
}

ViewFeed::~ViewFeed() { Stop(); }

void ViewFeed::Start() {
  server_.Start();
  thread_ = std::thread([this] { Run(); });
}

void ViewFeed::Stop() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
  server_.Stop();
}

void ViewFeed::Run() {
  using Steady = std::chrono::steady_clock;
  const auto period = std::chrono::duration_cast<Steady::duration>(std::chrono::duration<double>(1.0 / options_.rate));
  const auto map_period =
      std::chrono::duration_cast<Steady::duration>(std::chrono::duration<double>(options_.map_period));
  Steady::time_point next = Steady::now(), next_building = Steady::now();
  std::unique_lock<std::mutex> lock(mutex_);
  while (!stop_) {
    wake_.wait_until(lock, next, [this] { return stop_ || !commands_.empty(); });
    if (stop_) break;
    while (!commands_.empty()) {
      const view::ClientMessage m = commands_.front();
      commands_.pop_front();
      lock.unlock();
      Command(m);
      lock.lock();
    }
    const Steady::time_point now = Steady::now();
    if (now < next) continue;
    next = std::max(next + period, now);
    const bool building_due = now >= next_building;
    if (building_due) next_building = now + map_period;
    lock.unlock();
    try {
      PublishOnce(building_due);
    } catch (const std::exception& e) {
      spdlog::warn("view: {}", e.what());
    }
    lock.lock();
  }
}

void ViewFeed::PublishOnce(bool building_due) {
  const double now = sources_.clock.Now();
  const uint64_t stamp = view::StampNanoseconds(now);
  PublishMaps(building_due, stamp, now);
  const localization::PoseEstimate estimate = sources_.localizer.Estimate();
  if (estimate.valid) PublishPose(estimate, stamp);
  const navigation::Navigator& navigator = sources_.executive.navigator();
  if (server_.HasSubscribers(channels_.path)) {
    server_.Publish(channels_.path, stamp, view::PathJson(navigator.LegPath(), now, kMapFrame));
  }
  if (server_.HasSubscribers(channels_.path_ahead)) {
    server_.Publish(channels_.path_ahead, stamp,
                    view::PathJson(navigator.PathAhead(std::numeric_limits<double>::infinity()), now, kMapFrame));
  }
  const navigation::NavigationStatus s = navigator.Status();
  PublishSensed(s, stamp, now);
  if (server_.HasSubscribers(channels_.status)) {
    server_.Publish(channels_.status, stamp,
                    StatusJson(now, s, sources_.localizer.name(), estimate, sources_.executive).dump());
  }
  if (server_.HasSubscribers(channels_.mission)) {
    server_.Publish(channels_.mission, stamp, MissionJson(now, s, navigator).dump());
  }
}

void ViewFeed::PublishMaps(bool building_due, uint64_t stamp, double now) {
  // The served one when it changes (a subscriber gets the newest at once), the one being built
  // every map_period during a mapping run, the costmap when the planner rebuilds it.
  if (const auto served = sources_.maps.Get(); served && served->version != map_version_) {
    map_version_ = served->version;
    server_.Publish(channels_.map, stamp, view::OccupancyGridJson(served->grid, now, kMapFrame));
  }
  if (building_due && server_.HasSubscribers(channels_.map_building)) {
    const auto session = sources_.builder.session();
    if (session && session->status().active) {
      server_.Publish(channels_.map_building, stamp, view::OccupancyGridJson(*session->Map(), now, kMapFrame));
    }
  }
  if (server_.HasSubscribers(channels_.costmap)) {
    std::shared_ptr<const planning::Costmap> costmap = sources_.costmaps.Current();
    if (costmap && costmap != costmap_) {
      costmap_ = costmap;
      server_.Publish(channels_.costmap, stamp,
                      view::CostGridJson(costmap->grid(), CostmapCells(*costmap), now, kMapFrame));
    }
  }
}

void ViewFeed::PublishPose(const localization::PoseEstimate& estimate, uint64_t stamp) {
  if (server_.HasSubscribers(channels_.pose)) {
    double covariance[9];
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) covariance[3 * r + c] = estimate.covariance(r, c);
    server_.Publish(channels_.pose, stamp, view::PoseJson(estimate.pose, covariance, estimate.stamp, kMapFrame));
  }
  if (server_.HasSubscribers(channels_.transform)) {
    server_.Publish(channels_.transform, stamp,
                    view::FrameTransformJson(estimate.pose, estimate.stamp, kMapFrame, options_.robot_frame));
  }
}

void ViewFeed::PublishSensed(const navigation::NavigationStatus& s, uint64_t stamp, double now) {
  if (sources_.bridge && server_.HasSubscribers(channels_.scan) && sources_.bridge->scan_count() != scans_seen_) {
    scans_seen_ = sources_.bridge->scan_count();
    if (const auto scan = sources_.bridge->LatestScan()) {
      server_.Publish(
          channels_.scan, view::StampNanoseconds(scan->stamp),
          view::LaserScanJson(scan->ranges, scan->angle_min, scan->angle_increment, scan->stamp, options_.robot_frame));
    }
  }
  if (server_.HasSubscribers(channels_.people)) {
    std::vector<view::MovingDisc> discs;
    for (const navigation::TrackedPerson& p : sources_.executive.people()) {
      discs.push_back({"person " + std::to_string(p.id), p.position, p.velocity, 0.25, "person"});
    }
    server_.Publish(channels_.people, stamp, view::MovingDiscsJson(discs, now, kMapFrame));
  }
  if (server_.HasSubscribers(channels_.obstacles)) {
    std::vector<view::MovingDisc> discs;
    int i = 0;
    for (const planning::MovingBody& b : s.feedback.moving_obstacles) {
      discs.push_back(
          {"obstacle " + std::to_string(i++), b.position, b.velocity, b.radius, b.person ? "person" : "obstacle"});
    }
    server_.Publish(channels_.obstacles, stamp, view::MovingDiscsJson(discs, now, kMapFrame));
  }
}

void ViewFeed::Command(const view::ClientMessage& m) {
  if (m.topic != "/goal" && m.topic != "/cancel") {
    server_.SendStatus(m.connection, 1, "topic '" + m.topic + "' is not read by navd (it reads /goal and /cancel)");
    return;
  }
  if (m.access != view::Access::kCommand) {
    server_.SendStatus(m.connection, 2, m.topic + ": needs a token with the operator role");
    return;
  }
  try {
    if (m.topic == "/cancel") {
      const bool cancelled = sources_.executive.Cancel();
      server_.SendStatus(m.connection, 0, cancelled ? "cancelled" : "cancel: no active goal");
      spdlog::info("view: client {} cancelled the goal", m.connection);
      return;
    }
    const navigation::NavigateRequest request = ParseGoal(m.payload);
    const uint64_t id = sources_.executive.Navigate(request);
    spdlog::info("view: client {} sent goal {} to ({:.2f}, {:.2f})", m.connection, id, request.goal.x, request.goal.y);
    server_.SendStatus(m.connection, 0, "goal " + std::to_string(id) + " accepted");
  } catch (const Error& e) {
    server_.SendStatus(m.connection, 2, std::string(m.topic) + ": " + e.what());
  }
}

}  // namespace navd::server
