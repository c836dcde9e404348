#pragma once
// Lockstep between the simulator and the robots' controllers. Each controller reports the
// simulated time of its next control tick once it has finished the current one; the simulator
// does not step past a time some controller has not yet been given. Then what happens in
// simulated time does not depend on how loaded the machine is (a controller that falls behind
// the wall clock would otherwise act late and see sensors late), as Gazebo's lockstep.
//
// Until its first report a controller holds the simulation at its start: a run begins when its
// navd does (at 8x real time a navd a second late to start would find the world 8 s on, people
// walked up to a robot still waiting for its mission). A controller that does not report within
// the wall-clock timeout (a robot without navd), or stops answering, is released and held again
// from its next report (a navd that died and was restarted).
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <functional>
#include <limits>
#include <mutex>
#include <vector>

namespace navd::sim {

class LockstepGate {
 public:
  // robots: how many controllers may report; timeout: wall seconds a step waits for a controller.
  LockstepGate(size_t robots, double timeout);

  // Controller `robot` finished its tick and needs nothing until simulated time `next_tick` (s).
  // Called from DDS threads.
  void Report(size_t robot, double next_tick);

  // Blocks until every held controller has been given simulated time `t` (its next tick lies
  // ahead of t), or until the timeout. Returns the robots released by the timeout (normally none).
  // `while_held`, when given, is called every kRepeatPeriod of the wait (without the gate's lock):
  // navsim repeats the clock there, since a best-effort sample sent before a navd's reader had
  // matched is lost and that navd would never reach its tick.
  std::vector<size_t> WaitUntilAllowed(double t, const std::function<void()>& while_held = {});

  static constexpr double kRepeatPeriod = 0.05;  // s of wall time

  // Whether some controller holds the simulation (has not reported yet, or has, and not timed out).
  bool holding() const;

 private:
  bool AllowedLocked(double t) const;

  const double timeout_;
  mutable std::mutex mutex_;
  std::condition_variable cv_;
  struct Controller {
    bool held = true;  // at first: until it reports
    double next_tick = -std::numeric_limits<double>::infinity();
  };
  std::vector<Controller> controllers_;
};

}  // namespace navd::sim
