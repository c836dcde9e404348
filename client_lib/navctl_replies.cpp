#include "client_lib/navctl_replies.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <utility>

#include "client_lib/navctl_text.h"

namespace navd::navctl {

using nlohmann::json;

void PrintPath(const v1::ComputePathResponse& r, bool json_out) {
  if (json_out) {
    std::printf("%s\n", PlanJson(r.planner(), r.length(), r.planning_time(), r.expansions(), r.path()).dump().c_str());
  } else {
    std::printf("planner %s: %d waypoints, length %.3f m, planned in %.2f ms (%lu expansions)\n", r.planner().c_str(),
                r.path_size(), r.length(), r.planning_time() * 1e3, static_cast<unsigned long>(r.expansions()));
    for (const auto& p : r.path()) std::printf("  %.3f, %.3f\n", p.x(), p.y());
  }
}

void PrintPlanners(const v1::ListPlannersResponse& r, bool json_out) {
  json list = json::array();
  for (const auto& p : r.planners()) {
    json opts = json::array();
    for (const auto& o : p.options())
      opts.push_back({{"name", o.name()}, {"default", o.default_value()}, {"description", o.description()}});
    list.push_back(
        {{"name", p.name()}, {"description", p.description()}, {"default", p.is_default()}, {"options", opts}});
    if (!json_out)
      std::printf("%s%s  %s\n", p.name().c_str(), p.is_default() ? " (default)" : "", p.description().c_str());
  }
  if (json_out) std::printf("%s\n", json{{"planners", list}}.dump().c_str());
}

void PrintNavigationResult(const v1::NavigationResult& result, bool json_out) {
  if (json_out) {
    std::printf("%s\n", json{{"outcome", OutcomeText(result.outcome())},
                             {"message", result.message()},
                             {"final_pose", PoseJson(result.final_pose())},
                             {"distance_to_goal", result.distance_to_goal()},
                             {"elapsed", result.elapsed()},
                             {"path_length", result.path_length()}}
                            .dump()
                            .c_str());
  } else {
    std::printf("%s: %s; final pose (%.3f, %.3f, %.3f), %.3f m from the goal, %.1f s, path %.2f m\n",
                OutcomeText(result.outcome()), result.message().c_str(), result.final_pose().x(),
                result.final_pose().y(), result.final_pose().theta(), result.distance_to_goal(), result.elapsed(),
                result.path_length());
  }
}

void PrintPose(const v1::GetPoseResponse& r, bool json_out) {
  if (json_out) {
    std::printf("%s\n", json{{"pose", PoseJson(r.pose())},
                             {"covariance", std::vector<double>(r.covariance().begin(), r.covariance().end())},
                             {"stamp", r.stamp().sec() + r.stamp().nanosec() * 1e-9},
                             {"localizer", r.localizer()}}
                            .dump()
                            .c_str());
  } else {
    std::printf("pose (%.3f, %.3f, %.3f)  sigma_xy %.3f m  [%s]\n", r.pose().x(), r.pose().y(), r.pose().theta(),
                std::sqrt(std::max(0.0, r.covariance(0) + r.covariance(4))), r.localizer().c_str());
  }
}

void PrintStatus(const v1::GetStatusResponse& s, bool json_out) {
  if (json_out) {
    std::printf("%s\n", json{{"state", StateText(s.state())},
                             {"active", s.active()},
                             {"goal", PoseJson(s.goal())},
                             {"pose", PoseJson(s.feedback().pose())},
                             {"distance_remaining", s.feedback().distance_remaining()},
                             {"sensors_stale", s.sensors_stale()},
                             {"localization_lost", s.localization_lost()},
                             {"localization_losses", s.localization_losses()}}
                            .dump()
                            .c_str());
  } else {
    const std::string losses =
        s.localization_losses() > 0 ? ", pose lost " + std::to_string(s.localization_losses()) + "x since start" : "";
    std::printf("%s%s, pose (%.2f, %.2f, %.2f)%s%s%s\n", StateText(s.state()), s.active() ? " (goal active)" : "",
                s.feedback().pose().x(), s.feedback().pose().y(), s.feedback().pose().theta(),
                s.sensors_stale() ? ", sensors stale" : "", s.localization_lost() ? ", pose lost now" : "",
                losses.c_str());
  }
}

v1::SetSpeedZonesRequest ParseSpeedZones(const std::vector<std::string>& zone_specs) {
  v1::SetSpeedZonesRequest request;
  for (const std::string& spec : zone_specs) {
    const size_t a = spec.find(':'), b = spec.rfind(':');
    if (a == std::string::npos || a == b || a == 0) {
      throw std::runtime_error("--set '" + spec + "': expected NAME:X_MIN,Y_MIN,X_MAX,Y_MAX:MAX_SPEED");
    }
    const auto box = ParseTuple(spec.substr(a + 1, b - a - 1), "--set " + spec.substr(0, a), 4, 4);
    const auto speed = ParseTuple(spec.substr(b + 1), "--set " + spec.substr(0, a) + " max speed", 1, 1);
    v1::SpeedZone* z = request.add_zones();
    z->set_name(spec.substr(0, a));
    for (const auto& [x, y] : {std::pair{box[0], box[1]}, {box[2], box[1]}, {box[2], box[3]}, {box[0], box[3]}}) {
      v1::Point2D* p = z->add_area();
      p->set_x(x);
      p->set_y(y);
    }
    z->set_max_speed(speed[0]);
  }
  return request;
}

void PrintSpeedZones(const v1::SpeedZones& zones, bool json_out) {
  if (json_out) {
    json list = json::array();
    for (const auto& z : zones.zones()) {
      json area = json::array();
      for (const auto& p : z.area()) area.push_back({p.x(), p.y()});
      list.push_back({{"name", z.name()}, {"area", area}, {"max_speed", z.max_speed()}});
    }
    std::printf("%s\n", json{{"zones", list}}.dump().c_str());
  } else if (zones.zones().empty()) {
    std::printf("no speed zones\n");
  } else {
    for (const auto& z : zones.zones()) {
      std::printf("%s: at most %.2f m/s within", z.name().c_str(), z.max_speed());
      for (const auto& p : z.area()) std::printf(" (%.2f, %.2f)", p.x(), p.y());
      std::printf("\n");
    }
  }
}

void PrintMapInfo(const v1::MapInfo& m, bool json_out) {
  if (json_out) {
    std::printf("%s\n", json{{"name", m.name()},
                             {"width", m.width()},
                             {"height", m.height()},
                             {"resolution", m.resolution()},
                             {"origin", PoseJson(m.origin())},
                             {"version", m.version()}}
                            .dump()
                            .c_str());
  } else {
    std::printf("map '%s': %ux%u cells at %.3f m, origin (%.2f, %.2f), version %lu\n", m.name().c_str(), m.width(),
                m.height(), m.resolution(), m.origin().x(), m.origin().y(), static_cast<unsigned long>(m.version()));
  }
}

void PrintMappingStatus(const v1::MappingStatus& st, bool json_out) {
  if (json_out) {
    std::printf("%s\n", json{{"exists", st.exists()},
                             {"active", st.active()},
                             {"mode", st.mode() == v1::MAPPING_MODE_SLAM ? "slam" : "known_poses"},
                             {"scans", st.scans()},
                             {"dropped_scans", st.dropped_scans()},
                             {"nodes", st.nodes()},
                             {"loop_closures", st.loop_closures()},
                             {"pose", PoseJson(st.pose())},
                             {"width", st.info().width()},
                             {"height", st.info().height()},
                             {"resolution", st.info().resolution()},
                             {"version", st.version()}}
                            .dump()
                            .c_str());
  } else if (!st.exists()) {
    std::printf("no mapping run yet\n");
  } else {
    std::printf(
        "mapping %s (%s): %lu scans (%lu dropped), %u nodes, %u loop closures, %ux%u cells at %.3f m, "
        "pose (%.2f, %.2f, %.2f)\n",
        st.active() ? "active" : "stopped", st.mode() == v1::MAPPING_MODE_SLAM ? "slam" : "known poses",
        static_cast<unsigned long>(st.scans()), static_cast<unsigned long>(st.dropped_scans()), st.nodes(),
        st.loop_closures(), st.info().width(), st.info().height(), st.info().resolution(), st.pose().x(), st.pose().y(),
        st.pose().theta());
  }
}

}  // namespace navd::navctl
