#pragma once
// Two coarse balls about to collide off-centre in free space, stacked into one mesh with their
// body ranges: the several-bodies tests' scene (simulation and adjoint).

#include "mesh_fixtures.hpp"
#include "rbaa/material/material_field.hpp"
#include "rbaa/sim/simulator.hpp"

namespace rbaa::test {

struct TwoBalls {
  TetMesh mesh;
  std::vector<Body> bodies;
  SimulationSettings settings;
  MaterialField materials;
};

// Ball A (r 0.05) at the origin moving +x and spinning, ball B (r 0.04, stiffer, denser) ahead,
// offset in y so that the impact is off-centre.
inline TwoBalls two_balls(double gap = 0.02) {
  const TetMesh a = test::ball_mesh(0.05, 3, Eigen::Vector3d(0, 0, 0));
  const TetMesh b = test::ball_mesh(0.04, 3, Eigen::Vector3d(0.09 + gap, 0.03, 0.01));
  TwoBalls t;
  t.mesh.V.resize(a.num_vertices() + b.num_vertices(), 3);
  t.mesh.V << a.V, b.V;
  t.mesh.T.resize(a.num_tets() + b.num_tets(), 4);
  t.mesh.T << a.T, (b.T.array() + a.num_vertices()).matrix();
  Body A, B;
  A.name = "A";
  A.vertex_end = a.num_vertices();
  A.element_end = a.num_tets();
  A.velocity = Eigen::Vector3d(2, 0, 0);
  A.angular_velocity = Eigen::Vector3d(0, 0, 20);
  B.name = "B";
  B.vertex_begin = A.vertex_end;
  B.vertex_end = t.mesh.num_vertices();
  B.element_begin = A.element_end;
  B.element_end = t.mesh.num_tets();
  B.centre = Eigen::Vector3d(0.09 + gap, 0.03, 0.01);
  B.velocity = Eigen::Vector3d(-1, 0, 0);
  t.bodies = {A, B};
  t.settings.time_step = 1e-3;
  t.settings.num_steps = 40;
  t.settings.gravity.setZero();
  t.settings.d_hat = 4e-3;  // contact lasts several steps
  t.settings.kappa = 100.0;
  t.settings.newton_tolerance = 1e-12;
  t.settings.bodies = t.bodies;
  t.materials = MaterialField::uniform(t.mesh.num_tets(), 1e8, 0.3, 1000);
  t.materials.Y.tail(b.num_tets()).setConstant(5e8);
  t.materials.rho.tail(b.num_tets()).setConstant(3000);
  return t;
}

}  // namespace rbaa::test
