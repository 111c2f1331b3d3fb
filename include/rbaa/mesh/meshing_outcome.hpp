#pragma once
// What tetrahedralize's search for a cell size that gives the wanted tet count found: every
// size tried and its count, and, when the count missed the target, why in one line.

#include <string>
#include <vector>

namespace rbaa {

struct MeshingAttempt {
  double cell_size = 0;  ///< m
  int tets = 0;          ///< 0: meshing failed at this size
  std::string fault;     ///< why it failed (empty otherwise)
};

struct MeshingOutcome {
  int target_tets = 0;
  double tolerance = 0;  ///< relative, e.g. 0.05
  int tets = 0;          ///< in the mesh returned (the attempt closest to the target)
  std::vector<MeshingAttempt> attempts;  ///< in the order tried

  /// |tets / target_tets - 1| <= tolerance.
  bool within_tolerance() const;
  /// Why the count missed the target, one line without a trailing period (empty when within
  /// tolerance): a floor set by the surface's detail (the count hardly falls as the cells grow,
  /// because sharp features and the surface-approximation bound keep small elements), a jump
  /// across the target between neighbouring cell sizes, or attempts running out.
  std::string shortfall() const;
};

}  // namespace rbaa
