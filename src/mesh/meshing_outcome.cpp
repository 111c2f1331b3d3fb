#include "rbaa/mesh/meshing_outcome.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace rbaa {

bool MeshingOutcome::within_tolerance() const {
  return target_tets > 0 && std::abs(static_cast<double>(tets) / target_tets - 1.0) <= tolerance;
}

std::string MeshingOutcome::shortfall() const {
  if (within_tolerance()) return "";
  std::vector<MeshingAttempt> ok;
  int failed = 0;
  std::string fault;
  for (const MeshingAttempt& a : attempts) {
    if (a.tets > 0) {
      ok.push_back(a);
    } else {
      ++failed;
      fault = a.fault;
    }
  }
  std::sort(ok.begin(), ok.end(), [](const MeshingAttempt& a, const MeshingAttempt& b) {
    return a.cell_size < b.cell_size;
  });
  const double hi = target_tets * (1.0 + tolerance), lo = target_tets * (1.0 - tolerance);
  std::ostringstream why;
  why.precision(3);
  bool explained = false;
  // A jump: neighbouring cell sizes give counts on both sides of the band.
  for (size_t i = 0; i + 1 < ok.size() && !explained; ++i) {
    if (ok[i].tets > hi && ok[i + 1].tets < lo) {
      why << "the count jumps across the target between neighbouring cell sizes (" << ok[i].tets
          << " tets at " << ok[i].cell_size << " m, " << ok[i + 1].tets << " at "
          << ok[i + 1].cell_size << " m)";
      explained = true;
    }
  }
  if (!explained && !ok.empty() && tets > hi && ok.back().tets > hi) {
    // Too many tets even at the largest cell size that meshed. At a uniform size the count falls
    // like size^-3; a count that falls far less is held up by the surface's detail, and so is one
    // that cannot be lowered because every coarser size fails to mesh.
    const MeshingAttempt& small = ok.front();
    const MeshingAttempt& large = ok.back();
    const double growth = large.cell_size / small.cell_size;
    const double fall = static_cast<double>(small.tets) / large.tets;
    int coarser_failed = 0;
    double coarsest = 0;
    for (const MeshingAttempt& a : attempts) {
      if (a.tets == 0 && a.cell_size > large.cell_size) {
        ++coarser_failed;
        coarsest = std::max(coarsest, a.cell_size);
      }
    }
    if (growth >= 1.5 && fall < 0.5 * growth * growth * growth) {
      why << "the surface's detail sets a floor: cell sizes from " << small.cell_size << " to "
          << large.cell_size << " m gave " << small.tets << " to " << large.tets
          << " tets (sharp features and the surface-approximation bound keep small elements)";
    } else if (coarser_failed > 0) {
      why << "the surface's detail sets a floor: " << large.tets << " tets at " << large.cell_size
          << " m, and all " << coarser_failed << " coarser cell sizes tried (up to " << coarsest
          << " m) failed to mesh (" << fault << ")";
      failed = 0;  // said already
    } else {
      why << "the cell-size search ran out of its " << attempts.size()
          << " attempts while the count was still falling (" << large.tets << " tets at "
          << large.cell_size << " m)";
    }
    explained = true;
  }
  if (!explained && !ok.empty() && tets < lo && ok.front().tets < lo) {
    why << "the cell-size search ran out of its " << attempts.size()
        << " attempts while the count was still rising (" << ok.front().tets << " tets at "
        << ok.front().cell_size << " m)";
    explained = true;
  }
  if (!explained) {
    why << "no cell size of the " << attempts.size() << " tried gave a count within "
        << 100 * tolerance << " %";
  }
  if (failed > 0) {
    why << "; meshing failed at " << failed << " of the sizes (last: " << fault << ")";
  }
  return why.str();
}

}  // namespace rbaa
