#pragma once
// The time left in an Adam loop, for progress lines: the mean wall time of the loop's iterations
// done in this run (ProgressRow::seconds) times the iterations left,
//   eta = (sum of seconds / iterations done) * (total - last iteration - 1).
// Only the iterations' own time counts: the work before the loop (meshing, the reference run,
// attack.start: best_uniform's candidate simulations) is not iteration time; counted, it made the
// estimate of a best-uniform attack several times too long (1h22m with 25 min left).

#include "rbaa/opt/attack_loop.hpp"

namespace rbaa {

class IterationEta {
 public:
  /// Records a finished iteration of a loop of `total` iterations. A row whose index does not
  /// follow the previous one's begins another loop (the polish after the main loop), whose
  /// iterations take their own time: the mean restarts.
  void add(const ProgressRow& row, int total);
  /// Seconds until the current loop's last iteration ends (0 before any iteration).
  double seconds_left() const;

 private:
  int last_iteration_ = -1;
  int total_ = 0;
  int done_ = 0;
  double seconds_ = 0;
};

}  // namespace rbaa
