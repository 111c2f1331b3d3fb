// The contact module's broad and narrow phase on a ball against a basketball rim and backboard,
// and (issue 19 item 6) the share of a Newton iteration spent in contact, measured in one run on
// the ball + rim step and a four-cube stack. The ball is an icosphere of the SPEC's radius
// 0.121 m (a CGAL tet ball for the Newton step), the rim a torus tube (0.4572 m inner diameter,
// 1 cm tube), the backboard one rectangle (two triangles); the ball sits 0.5 mm from the rim and
// moves 3.5 cm towards it and sideways in the step, about one 0.01 s step at the ball's speed.
// d_hat = 1e-3 m.
//
//   ./build/benchmarks/bench_contact

#include <benchmark/benchmark.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>
#include <utility>
#include <vector>

#include "rbaa/contact/additive_ccd.hpp"
#include "rbaa/contact/broad_phase.hpp"
#include "rbaa/contact/edge_edge.hpp"
#include "rbaa/contact/edge_edge_mollifier.hpp"
#include "rbaa/contact/point_triangle.hpp"
#include "rbaa/contact/static_mesh_broad_phase.hpp"
#include "rbaa/mesh/primitives.hpp"
#include "rbaa/mesh/tetrahedralize.hpp"
#include "rbaa/sim/barrier_stiffness.hpp"
#include "rbaa/sim/mass_matrix.hpp"
#include "rbaa/sim/simulator.hpp"

namespace {

using rbaa::contact::Edges;
using rbaa::contact::Positions;
using rbaa::contact::Triangles;

constexpr double kDHat = 1e-3;

struct World {
  Positions V0, V1;
  Triangles F;
  Edges E;
  std::vector<int> body;  ///< per vertex: 0 ball, 1 rim, 2 backboard
};

void append(World& w, const Positions& V, const Triangles& F, int body) {
  const Eigen::Index offset = w.V0.rows();
  w.V0.conservativeResize(offset + V.rows(), 3);
  w.V0.bottomRows(V.rows()) = V;
  const Eigen::Index f0 = w.F.rows();
  w.F.conservativeResize(f0 + F.rows(), 3);
  w.F.bottomRows(F.rows()) = F.array() + int(offset);
  w.body.resize(w.V0.rows(), body);
}

// A torus about +z: major radius R, tube radius r, n x m quads split in two.
void torus(double R, double r, int n, int m, Positions& V, Triangles& F) {
  V.resize(n * m, 3);
  F.resize(2 * n * m, 3);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j) {
      const double u = 2 * M_PI * i / n, v = 2 * M_PI * j / m;
      V.row(i * m + j) << (R + r * std::cos(v)) * std::cos(u), (R + r * std::cos(v)) * std::sin(u),
          r * std::sin(v);
      const int a = i * m + j, b = i * m + (j + 1) % m, c = ((i + 1) % n) * m + j,
                d = ((i + 1) % n) * m + (j + 1) % m;
      F.row(2 * (i * m + j)) << a, c, d;
      F.row(2 * (i * m + j) + 1) << a, d, b;
    }
}

World make_world(int subdivisions) {
  World w;
  const rbaa::SurfaceMesh ball = rbaa::sphere_surface(0.121, subdivisions);
  Positions rim_V;
  Triangles rim_F;
  const double rim_R = 0.4572 / 2 + 0.01, rim_r = 0.01;
  torus(rim_R, rim_r, 96, 12, rim_V, rim_F);
  // The ball just above the rim's front, 0.5 mm from the tube.
  const Eigen::RowVector3d centre(rim_R, 0, rim_r + 0.121 + 5e-4);
  Positions ball_V = ball.V;
  ball_V.rowwise() += centre;
  append(w, ball_V, ball.F, 0);
  append(w, rim_V, rim_F, 1);
  // The backboard: x = -(rim_R + 0.151), 1.8 m wide, 1.05 m high.
  Positions board(4, 3);
  const double bx = -(rim_R + 0.151);
  board << bx, -0.9, -0.3, bx, 0.9, -0.3, bx, 0.9, 0.75, bx, -0.9, 0.75;
  Triangles board_F(2, 3);
  board_F << 0, 1, 2, 0, 2, 3;
  append(w, board, board_F, 2);
  w.V1 = w.V0;
  for (Eigen::Index v = 0; v < w.V0.rows(); ++v)
    if (w.body[v] == 0) w.V1.row(v) += Eigen::RowVector3d(-0.02, 0.01, -0.025);
  std::set<std::pair<int, int>> edges;
  for (Eigen::Index f = 0; f < w.F.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = w.F(f, k), b = w.F(f, (k + 1) % 3);
      edges.insert({std::min(a, b), std::max(a, b)});
    }
  w.E.resize(edges.size(), 2);
  int i = 0;
  for (const auto& [a, b] : edges) w.E.row(i++) << a, b;
  return w;
}

const World& world() {
  static const World w = make_world(4);
  static bool printed = false;
  if (!printed) {
    printed = true;
    std::printf("ball + rim + backboard: %lld vertices, %lld triangles, %lld edges\n",
                (long long)w.V0.rows(), (long long)w.F.rows(), (long long)w.E.rows());
  }
  return w;
}

// Ball, rim and backboard each a group; the rim and the backboard could share one (both static).
const std::vector<int>& body_groups() { return world().body; }

Eigen::Vector3d row(const Positions& V, int v) { return V.row(v).transpose(); }

// The same world as the simulator's mesh-obstacle form sees it (mesh_obstacle_form.cpp): the
// rim and the backboard stacked into one StaticMeshBroadPhase, built once (obstacles never move),
// and the ball the moving surface, its vertices, triangles and edges indexing its own positions.
struct BallAndObstacles {
  Positions ball0, ball1;  // the ball's vertices at the step's start and end
  Triangles ball_F;
  Edges ball_E;
  std::vector<int> ball_vertices;
  rbaa::contact::StaticMeshBroadPhase obstacles;
};

const BallAndObstacles& ball_and_obstacles() {
  static const BallAndObstacles b = [] {
    const World& w = world();
    BallAndObstacles out;
    // make_world appends the ball first: its vertices and triangles are the leading rows.
    const int nb = static_cast<int>(std::count(w.body.begin(), w.body.end(), 0));
    Eigen::Index nf = 0;
    while (nf < w.F.rows() && w.body[w.F(nf, 0)] == 0) ++nf;
    out.ball0 = w.V0.topRows(nb);
    out.ball1 = w.V1.topRows(nb);
    out.ball_F = w.F.topRows(nf);
    out.ball_E = rbaa::contact::unique_edges(out.ball_F);
    for (int v = 0; v < nb; ++v) out.ball_vertices.push_back(v);
    Positions V = w.V0.bottomRows(w.V0.rows() - nb);
    Triangles F = w.F.bottomRows(w.F.rows() - nf).array() - nb;
    Edges E = rbaa::contact::unique_edges(F);
    out.obstacles = rbaa::contact::StaticMeshBroadPhase(std::move(V), std::move(F), std::move(E));
    return out;
  }();
  return b;
}

void candidate_counters(benchmark::State& state, const rbaa::contact::StaticMeshCandidates& c) {
  state.counters["vertex_triangle"] = double(c.vertex_triangle.size());
  state.counters["triangle_vertex"] = double(c.triangle_vertex.size());
  state.counters["edge_edge"] = double(c.edge_edge.size());
}

// Candidates swept over the step V0 -> V1 (the CCD's, once per Newton iteration: the line search
// only shortens the step, so boxes over the whole step cover it). broad_phase.hpp's generic
// functions, which rebuild both sides' trees per call: what body-body contact uses. Ball against
// rim and backboard in the simulator goes through BM_StaticMeshQuery's path instead.
void BM_BroadPhase(benchmark::State& state) {
  const World& w = world();
  std::size_t vt = 0, ee = 0;
  for (auto _ : state) {
    vt = rbaa::contact::vertex_triangle_candidates(w.V0, w.V1, w.F, kDHat, body_groups()).size();
    ee = rbaa::contact::edge_edge_candidates(w.V0, w.V1, w.E, kDHat, body_groups()).size();
  }
  state.counters["vertex_triangle"] = double(vt);
  state.counters["edge_edge"] = double(ee);
}
BENCHMARK(BM_BroadPhase)->Unit(benchmark::kMillisecond);

// The same at one configuration (V1 = V0): the active set's candidates, once per Newton iterate.
void BM_BroadPhaseStatic(benchmark::State& state) {
  const World& w = world();
  std::size_t vt = 0, ee = 0;
  for (auto _ : state) {
    vt = rbaa::contact::vertex_triangle_candidates(w.V0, w.V0, w.F, kDHat, body_groups()).size();
    ee = rbaa::contact::edge_edge_candidates(w.V0, w.V0, w.E, kDHat, body_groups()).size();
  }
  state.counters["vertex_triangle"] = double(vt);
  state.counters["edge_edge"] = double(ee);
}
BENCHMARK(BM_BroadPhaseStatic)->Unit(benchmark::kMillisecond);

// The broad phase the simulator runs for the ball against the rim and the backboard:
// StaticMeshBroadPhase::query with the obstacles' trees built once, outside the loop, called as
// MeshObstacleForm calls it. Arg 0: at one configuration, inflated by d_hat (the active set's
// candidates, once per new iterate); arg 1: swept over the step, inflated by d_hat (max_step_size's
// CCD candidates, once per line search; is_step_valid asks again with no inflation).
void BM_StaticMeshQuery(benchmark::State& state) {
  const BallAndObstacles& b = ball_and_obstacles();
  const Positions& end = state.range(0) == 1 ? b.ball1 : b.ball0;
  rbaa::contact::StaticMeshCandidates c;
  for (auto _ : state) {
    c = b.obstacles.query(b.ball0, end, b.ball_vertices, b.ball_F, b.ball_E, kDHat);
    benchmark::DoNotOptimize(c.vertex_triangle.data());
  }
  candidate_counters(state, c);
}
BENCHMARK(BM_StaticMeshQuery)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

// What the contact form does per Newton iteration on the active pairs: classify, squared
// distance, gradient and Hessian (and the mollifier for edge-edge), for every candidate at V0.
void BM_NarrowPhaseDerivatives(benchmark::State& state) {
  const World& w = world();
  const auto vt = rbaa::contact::vertex_triangle_candidates(w.V0, w.V0, w.F, kDHat, body_groups());
  const auto ee = rbaa::contact::edge_edge_candidates(w.V0, w.V0, w.E, kDHat, body_groups());
  int active = 0;
  for (auto _ : state) {
    active = 0;
    double sink = 0;
    for (const auto& c : vt) {
      const auto p = row(w.V0, c.vertex), t0 = row(w.V0, w.F(c.triangle, 0)),
                 t1 = row(w.V0, w.F(c.triangle, 1)), t2 = row(w.V0, w.F(c.triangle, 2));
      const auto type = rbaa::contact::point_triangle_distance_type(p, t0, t1, t2);
      const double d = rbaa::contact::point_triangle_distance(p, t0, t1, t2, type);
      if (d >= kDHat * kDHat) continue;
      ++active;
      sink += rbaa::contact::point_triangle_distance_gradient(p, t0, t1, t2, type).sum();
      sink += rbaa::contact::point_triangle_distance_hessian(p, t0, t1, t2, type).sum();
    }
    for (const auto& c : ee) {
      const auto a0 = row(w.V0, w.E(c.edge_a, 0)), a1 = row(w.V0, w.E(c.edge_a, 1)),
                 b0 = row(w.V0, w.E(c.edge_b, 0)), b1 = row(w.V0, w.E(c.edge_b, 1));
      const auto type = rbaa::contact::edge_edge_distance_type(a0, a1, b0, b1);
      const double d = rbaa::contact::edge_edge_distance(a0, a1, b0, b1, type);
      if (d >= kDHat * kDHat) continue;
      ++active;
      const double eps_x = rbaa::contact::edge_edge_mollifier_threshold(a0, a1, b0, b1);
      sink += rbaa::contact::edge_edge_distance_gradient(a0, a1, b0, b1, type).sum();
      sink += rbaa::contact::edge_edge_distance_hessian(a0, a1, b0, b1, type).sum();
      sink += rbaa::contact::edge_edge_mollifier_hessian(a0, a1, b0, b1, eps_x).sum();
    }
    benchmark::DoNotOptimize(sink);
  }
  state.counters["candidates"] = double(vt.size() + ee.size());
  state.counters["active"] = active;
}
BENCHMARK(BM_NarrowPhaseDerivatives)->Unit(benchmark::kMillisecond);

// The line search's max_step_size as MeshObstacleForm runs it: additive CCD of every candidate
// that StaticMeshBroadPhase::query finds swept over the step V0 -> V1 (inflated by d_hat), the
// obstacles' points fixed. The query itself runs once, outside (BM_StaticMeshQuery/1 times it).
void BM_Ccd(benchmark::State& state) {
  const BallAndObstacles& b = ball_and_obstacles();
  const rbaa::contact::StaticMeshCandidates c =
      b.obstacles.query(b.ball0, b.ball1, b.ball_vertices, b.ball_F, b.ball_E, kDHat);
  const Positions& O = b.obstacles.V();
  double toi = 1;
  for (auto _ : state) {
    toi = 1;
    for (const auto& [v, t] : c.vertex_triangle) {
      const Triangles& F = b.obstacles.F();
      const Eigen::Vector3d a = row(O, F(t, 0)), bb = row(O, F(t, 1)), cc = row(O, F(t, 2));
      toi = std::min(toi, rbaa::contact::point_triangle_max_step_size(row(b.ball0, v), a, bb, cc,
                                                                      row(b.ball1, v), a, bb, cc));
    }
    for (const auto& [t, v] : c.triangle_vertex) {
      const Eigen::Vector3d p = row(O, v);
      const int i = b.ball_F(t, 0), j = b.ball_F(t, 1), k = b.ball_F(t, 2);
      toi = std::min(toi, rbaa::contact::point_triangle_max_step_size(
                              p, row(b.ball0, i), row(b.ball0, j), row(b.ball0, k), p,
                              row(b.ball1, i), row(b.ball1, j), row(b.ball1, k)));
    }
    for (const auto& [e, oe] : c.edge_edge) {
      const Edges& E = b.obstacles.E();
      const Eigen::Vector3d o0 = row(O, E(oe, 0)), o1 = row(O, E(oe, 1));
      const int i = b.ball_E(e, 0), j = b.ball_E(e, 1);
      toi = std::min(
          toi, rbaa::contact::edge_edge_max_step_size(row(b.ball0, i), row(b.ball0, j), o0, o1,
                                                      row(b.ball1, i), row(b.ball1, j), o0, o1));
    }
    benchmark::DoNotOptimize(toi);
  }
  state.counters["candidates"] =
      double(c.vertex_triangle.size() + c.triangle_vertex.size() + c.edge_edge.size());
  state.counters["toi"] = toi;
}
BENCHMARK(BM_Ccd)->Unit(benchmark::kMillisecond);

}  // namespace

// The Newton-step benchmarks' counters from their sums over the benchmark's iterations.
void report_step(benchmark::State& state, double step, double contact, int iterations, int pairs) {
  state.counters["newton_iterations"] = double(iterations) / state.iterations();
  state.counters["ms_per_iteration"] = 1e3 * step / iterations;
  state.counters["contact_ms_per_iteration"] = 1e3 * contact / iterations;
  state.counters["contact_share"] = contact / step;
  state.counters["active_pairs"] = pairs;
}

// Issue 19 item 6 in one run: the paper's ball (CGAL, 9056 tets target, Y 1e13) 0.5 mm above the
// rim moving (-2, 1, -2.5) m/s, one 0.01 s contact step with the rim and backboard as static mesh
// obstacles. Counters: Newton iterations of the step, wall ms per iteration, and the ms per
// iteration spent inside the mesh-obstacle form (its broad phase, narrow phase, derivatives and
// CCD, timed by IncrementalPotential::form_seconds), with its share of the iteration.
void BM_BallAgainstRimNewtonStep(benchmark::State& state) {
  static const rbaa::TetMesh ball = [] {
    rbaa::ShapeParameters p;
    p.radius = 0.121;
    return rbaa::mesh_shape("sphere", 9056, p);
  }();
  const World& w = world();
  rbaa::SimulationSettings s;
  s.time_step = 0.01;
  s.num_steps = 1;
  s.d_hat = kDHat;
  for (int body : {1, 2}) {
    rbaa::ObstacleMesh o;
    std::vector<int> ids(w.V0.rows(), -1);
    int n = 0;
    for (Eigen::Index v = 0; v < w.V0.rows(); ++v) {
      if (w.body[v] == body) ids[v] = n++;
    }
    o.V.resize(n, 3);
    for (Eigen::Index v = 0; v < w.V0.rows(); ++v) {
      if (ids[v] >= 0) o.V.row(ids[v]) = w.V0.row(v);
    }
    int f = 0;
    for (Eigen::Index t = 0; t < w.F.rows(); ++t) f += w.body[w.F(t, 0)] == body;
    o.F.resize(f, 3);
    f = 0;
    for (Eigen::Index t = 0; t < w.F.rows(); ++t) {
      if (w.body[w.F(t, 0)] != body) continue;
      for (int k = 0; k < 3; ++k) o.F(f, k) = ids[w.F(t, k)];
      ++f;
    }
    o.name = body == 1 ? "rim" : "backboard";
    s.obstacle_meshes.push_back(o);
  }
  // The tet ball where the surface ball of world() is: 0.5 mm above the rim's tube.
  rbaa::TetMesh placed = ball;
  const double rim_R = 0.4572 / 2 + 0.01, rim_r = 0.01;
  placed.V.rowwise() += Eigen::RowVector3d(rim_R, 0, rim_r + 0.121 + 5e-4);
  const Eigen::Vector3d velocity(-2, 1, -2.5);
  const double mass =
      2500 * rbaa::vertex_masses(placed, Eigen::VectorXd::Ones(placed.num_tets())).sum();
  s.kappa = rbaa::barrier_stiffness_from_energy(mass, velocity.norm(), kDHat);
  rbaa::Simulator sim(placed, rbaa::MaterialField::uniform(placed.num_tets(), 1e13, 0.28, 2500), s);
  const Eigen::VectorXd q0 = sim.rest_positions();
  const Eigen::VectorXd v0 = rbaa::rigid_velocities(q0, placed.V.colwise().mean().transpose(),
                                                    velocity, Eigen::Vector3d::Zero());
  double step = 0, contact = 0;
  int iterations = 0, pairs = 0;
  for (auto _ : state) {
    sim.reset(q0, v0);
    sim.potential().reset_timers();
    const rbaa::StepStats st = sim.advance();
    step += st.seconds;
    contact += sim.potential().form_seconds(*sim.mesh_obstacle_form());
    iterations += st.newton_iterations;
    pairs = st.active_pairs;
  }
  report_step(state, step, contact, iterations, pairs);
}
BENCHMARK(BM_BallAgainstRimNewtonStep)->Unit(benchmark::kMillisecond);

// Four 5 cm cubes (CGAL, ~500 tets each, Y 1e10) stacked 0.5 mm apart on the floor z = 0, one
// 0.01 s step under gravity, with friction mu between the cubes and against the floor.
struct FourCubes {
  rbaa::TetMesh stack;
  rbaa::SimulationSettings settings;
};

FourCubes four_cube_stack(double mu) {
  static const rbaa::TetMesh cube = [] {
    rbaa::ShapeParameters p;
    p.side = 0.05;
    return rbaa::mesh_shape("cube", 500, p);
  }();
  const int n = 4;
  FourCubes f;
  rbaa::TetMesh& stack = f.stack;
  stack.V.resize(n * cube.num_vertices(), 3);
  stack.T.resize(n * cube.num_tets(), 4);
  std::vector<rbaa::Body> bodies;
  const double lowest = cube.V.col(2).minCoeff();
  for (int b = 0; b < n; ++b) {
    rbaa::Body body;
    body.name = "cube " + std::to_string(b);
    body.vertex_begin = b * cube.num_vertices();
    body.vertex_end = (b + 1) * cube.num_vertices();
    body.element_begin = b * cube.num_tets();
    body.element_end = (b + 1) * cube.num_tets();
    stack.V.middleRows(body.vertex_begin, cube.num_vertices()) =
        cube.V.rowwise() + Eigen::RowVector3d(0, 0, 5e-4 - lowest + b * (0.05 + 5e-4));
    stack.T.middleRows(body.element_begin, cube.num_tets()) = cube.T.array() + body.vertex_begin;
    bodies.push_back(body);
  }
  rbaa::SimulationSettings& s = f.settings;
  s.time_step = 0.01;
  s.num_steps = 1;
  s.d_hat = kDHat;
  s.planes = {rbaa::Plane{}};
  s.planes[0].friction = mu;
  s.bodies = bodies;
  s.body_friction = Eigen::MatrixXd::Constant(n, n, mu);
  s.body_friction.diagonal().setZero();
  const double mass = 2500 * 0.05 * 0.05 * 0.05 * n;
  s.kappa = rbaa::barrier_stiffness_from_energy(mass, std::sqrt(2 * 9.8 * 0.1), kDHat);
  return f;
}

// The frictionless stack: every face pair in body-body contact. Counters as above, with the
// body-contact form's time (its broad phase, narrow phase, derivatives and CCD).
void BM_FourCubeStackNewtonStep(benchmark::State& state) {
  const FourCubes f = four_cube_stack(0.0);
  rbaa::Simulator sim(f.stack, rbaa::MaterialField::uniform(f.stack.num_tets(), 1e10, 0.3, 2500),
                      f.settings);
  const Eigen::VectorXd q0 = sim.rest_positions();
  const Eigen::VectorXd v0 = Eigen::VectorXd::Zero(q0.size());
  double step = 0, contact = 0;
  int iterations = 0, pairs = 0;
  for (auto _ : state) {
    sim.reset(q0, v0);
    sim.potential().reset_timers();
    const rbaa::StepStats st = sim.advance();
    step += st.seconds;
    contact += sim.potential().form_seconds(*sim.body_contact_form()) +
               sim.potential().form_seconds(sim.contact_form());
    iterations += st.newton_iterations;
    pairs = st.active_pairs;
  }
  report_step(state, step, contact, iterations, pairs);
}
BENCHMARK(BM_FourCubeStackNewtonStep)->Unit(benchmark::kMillisecond);

// The same step with the paper's friction, mu = 0.4 between the cubes and against the floor
// (SPEC section 7's four-cube scene): arg 0 from rest (static friction: the lagged pairs hold,
// no slip), arg 1 with the top cube thrown sideways at 0.5 m/s (it slides on the cube below).
// Counters as above, plus the friction forms' time (mesh pairs and the floor, lagging included)
// per iteration and its share, and the lagged friction pairs.
void BM_FourCubeStackFrictionNewtonStep(benchmark::State& state) {
  const FourCubes f = four_cube_stack(0.4);
  rbaa::Simulator sim(f.stack, rbaa::MaterialField::uniform(f.stack.num_tets(), 1e10, 0.3, 2500),
                      f.settings);
  const Eigen::VectorXd q0 = sim.rest_positions();
  Eigen::VectorXd v0 = Eigen::VectorXd::Zero(q0.size());
  if (state.range(0) == 1) {
    const rbaa::Body& top = f.settings.bodies.back();
    for (int v = top.vertex_begin; v < top.vertex_end; ++v) v0[3 * v] = 0.5;
  }
  double step = 0, contact = 0, friction = 0;
  int iterations = 0, pairs = 0, lagged = 0;
  for (auto _ : state) {
    sim.reset(q0, v0);
    sim.potential().reset_timers();
    const rbaa::StepStats st = sim.advance();
    step += st.seconds;
    contact += sim.potential().form_seconds(*sim.body_contact_form()) +
               sim.potential().form_seconds(sim.contact_form());
    friction += sim.potential().form_seconds(*sim.pair_friction_form()) +
                sim.potential().form_seconds(*sim.plane_friction_form());
    iterations += st.newton_iterations;
    pairs = st.active_pairs;
    lagged = sim.pair_friction_form()->num_lagged_pairs() +
             sim.plane_friction_form()->num_lagged_pairs();
  }
  report_step(state, step, contact, iterations, pairs);
  state.counters["friction_ms_per_iteration"] = 1e3 * friction / iterations;
  state.counters["friction_share"] = friction / step;
  state.counters["lagged_friction_pairs"] = lagged;
}
BENCHMARK(BM_FourCubeStackFrictionNewtonStep)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
