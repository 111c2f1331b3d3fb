#pragma once
// Objectives of a simulated trajectory (SPEC section 4) with the derivatives the adjoint consumes:
// dC/dq_k for any position k and, where the objective weighs positions with the object's own
// masses, dC/d(material) directly.
//
// * UndirectedTrajectoryObjective: C = -||q_N - q_ref,N||^2_Mref / (m0_ref L^2), the undirected
//   attack's trajectory term (Mref the reference's mass matrix, m0_ref its mass, L its radius of
//   gyration; q_ref,N the final positions of a fixed reference run).
// * Observables (a scalar of the trajectory, e.g. a centre-of-mass coordinate at step k) and the
//   DirectedObjective C = sum_i weight_i (o_i - target_i)^2 built from them.
//
// In a world of several bodies stacked into one mesh (sim/world.hpp) each takes the body it
// measures: the undirected term of the attacked body A, the centre of mass of a scored body B.
// Their seeds are full-length (3 #V per position, #T per material field) with zeros outside the
// body.

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <memory>
#include <vector>

#include "rbaa/diff/adjoint.hpp"
#include "rbaa/material/material_field.hpp"
#include "rbaa/mesh/tet_mesh.hpp"
#include "rbaa/sim/trajectory.hpp"
#include "rbaa/sim/world.hpp"

namespace rbaa {

/// to += scale * from (entry-wise; empty entries are zero).
void add_scaled(TrajectorySeed& to, double scale, const TrajectorySeed& from);

class TrajectoryObjective {
 public:
  virtual ~TrajectoryObjective() = default;
  /// C of a trajectory of the object with `materials`. With seed != nullptr also sets *seed to
  /// dC/dq_k (N + 1 entries) and the direct material derivatives.
  virtual double evaluate(const Trajectory& trajectory, const MaterialField& materials,
                          TrajectorySeed* seed) const = 0;
};

class UndirectedTrajectoryObjective : public TrajectoryObjective {
 public:
  /// `reference_mass`: Mref (3 #V square; the lower triangle is read), `reference_final`: q_ref(T)
  /// (3 #V), m0_ref (kg), L (m).
  UndirectedTrajectoryObjective(Eigen::SparseMatrix<double> reference_mass,
                                Eigen::VectorXd reference_final, double m0_ref, double L);

  /// The reference (`rest`, uniform density `reference_rho`, consistent mass) and its final
  /// positions; m0_ref and L from its exact moments.
  static std::shared_ptr<UndirectedTrajectoryObjective> from_reference(
      const TetMesh& rest, double reference_rho, const Eigen::VectorXd& reference_final);
  /// The same for one body of a stacked mesh: Mref, m0_ref and L of `body`'s elements alone (the
  /// other bodies carry no weight in the gap); `reference_final` is the whole world's (3 #V).
  /// A body covering the whole mesh gives the single-body objective above, bit for bit.
  static std::shared_ptr<UndirectedTrajectoryObjective> from_reference(
      const TetMesh& rest, double reference_rho, const Eigen::VectorXd& reference_final,
      const Body& body);

  /// -(d^T Mref d) / (m0_ref L^2), d = q_N - q_ref(T); dC/dq_N = -2 Mref d / (m0_ref L^2).
  double evaluate(const Trajectory& trajectory, const MaterialField& materials,
                  TrajectorySeed* seed) const override;

  /// The gap in metres, sqrt(||q - q_ref(T)||^2_Mref / m0_ref) (SPEC section 4).
  double gap(const Eigen::VectorXd& q_final) const;
  double m0_ref() const { return m0_; }
  double length() const { return L_; }
  const Eigen::VectorXd& reference_final() const { return q_ref_; }

 private:
  Eigen::SparseMatrix<double> M_;
  Eigen::VectorXd q_ref_;
  double m0_, L_;
};

/// A scalar of a trajectory whose derivatives the adjoint can take.
class Observable {
 public:
  virtual ~Observable() = default;
  /// The value; with gradient != nullptr also sets *gradient to its derivatives (as a seed).
  virtual double evaluate(const Trajectory& trajectory, const MaterialField& materials,
                          TrajectorySeed* gradient) const = 0;
};

/// direction . centre of mass at position `step` (negative: counted from the end, -1 = q_N), with
/// the object's own vertex masses (so it depends on rho and alpha directly).
class CentreOfMassObservable : public Observable {
 public:
  /// The centre of mass of the whole mesh.
  CentreOfMassObservable(const TetMesh& rest, const Eigen::Vector3d& direction, int step = -1);
  /// The centre of mass of one body of a stacked mesh: its elements' masses at its vertices.
  CentreOfMassObservable(const TetMesh& rest, const Body& body, const Eigen::Vector3d& direction,
                         int step = -1);
  double evaluate(const Trajectory& trajectory, const MaterialField& materials,
                  TrajectorySeed* gradient) const override;

 private:
  Tets tets_;
  Eigen::VectorXd volumes_;
  int num_vertices_;
  int num_tets_;
  // The body measured: its element and vertex ranges (the whole mesh by default).
  int element_begin_, element_end_, vertex_begin_, vertex_end_;
  Eigen::Vector3d direction_;
  int step_;
};

/// C = sum_i weight_i (o_i - target_i)^2 (SPEC section 4's directed objective).
class DirectedObjective : public TrajectoryObjective {
 public:
  struct Term {
    std::shared_ptr<const Observable> observable;
    double target = 0;
    double weight = 1;
  };
  explicit DirectedObjective(std::vector<Term> terms) : terms_(std::move(terms)) {}
  double evaluate(const Trajectory& trajectory, const MaterialField& materials,
                  TrajectorySeed* seed) const override;

 private:
  std::vector<Term> terms_;
};

}  // namespace rbaa
