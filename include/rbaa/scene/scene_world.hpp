#pragma once
// What scene/ derives from a config for the simulator: its settings and its barrier stiffness.

#include "rbaa/mesh/tet_mesh.hpp"
#include "rbaa/scene/scene.hpp"
#include "rbaa/sim/simulator.hpp"

namespace rbaa {

/// Settings of a scene: its h, steps = round(duration / h), integrator, mass model, gravity,
/// planes, d_hat and Newton settings, with the given (frozen) kappa.
SimulationSettings simulation_settings(const Scene& scene, double kappa);

/// scene.kappa if positive, else the energy rule (sim/barrier_stiffness.hpp) for the scene's
/// reference object (`placed`: the placed reference mesh, density scene.reference_rho). Throws
/// rbaa::InputError if the rule has nothing to go on (no speed and no fall) and the scene sets no
/// kappa.
double scene_barrier_stiffness(const Scene& scene, const TetMesh& placed);

}  // namespace rbaa
