#include "rbaa/opt/iteration_eta.hpp"

#include <algorithm>

namespace rbaa {

void IterationEta::add(const ProgressRow& row, int total) {
  if (row.iteration <= last_iteration_) {
    done_ = 0;
    seconds_ = 0;
  }
  last_iteration_ = row.iteration;
  total_ = total;
  ++done_;
  seconds_ += row.seconds;
}

double IterationEta::seconds_left() const {
  if (done_ == 0) return 0;
  return seconds_ / done_ * std::max(0, total_ - last_iteration_ - 1);
}

}  // namespace rbaa
