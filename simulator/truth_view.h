#pragma once
// navsim's live view (navsim --view HOST:PORT): the same Foxglove WebSocket server and page as
// navd's, with the ground truth: the world's map, every robot, person and moving obstacle where
// they really are (map frame, with their velocity), so a person can set it beside navd's view and
// compare what navd believes with what is. Encoding runs on the simulation's thread, at most
// `rate` times per wall second and only for channels someone subscribes to.
#include <chrono>

#include "simulator/simulation.h"
#include "view/foxglove_server.h"

namespace navd::sim {

class TruthView {
 public:
  // Throws navd::Error when the listener cannot start.
  TruthView(view::FoxgloveServerOptions options, const Simulation& simulation, double rate = 10.0);
  int port() const { return server_.port(); }
  // After a simulation step: publishes the truth when its period has passed.
  void Update(const Simulation& simulation);

 private:
  view::FoxgloveServer server_;
  uint32_t map_, robots_, people_, obstacles_;
  std::chrono::steady_clock::duration period_;
  std::chrono::steady_clock::time_point next_;
};

}  // namespace navd::sim
