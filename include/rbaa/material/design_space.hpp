#pragma once
// The parameterisation layer between the optimiser and the simulator (SPEC section 4): a design
// vector theta of unconstrained variables maps, through one tanh box map per field, to a
// MaterialField; a material-space gradient (dC/dY, dC/dnu, dC/drho, dC/dalpha per element) chains
// back to dC/dtheta. Only this class knows the layout of theta.
//
// Layout of theta: the chosen fields' blocks in the fixed order Y, nu, rho, alpha. Y, nu and rho
// have one entry per designed element (#designed, in increasing element order); alpha has one
// entry per designed interior element (#interior, in increasing element order). Boundary elements
// (a boundary face, or with boundary_by_vertex any boundary vertex) keep alpha = 1 and are not in
// theta. Fields that are not optimised keep their initial values.
//
// The element mask: in a world of several bodies stacked into one mesh, only the attacked body's
// elements are designed (attack body A, score body B). Every other element keeps the material
// given to hold_fixed_elements (its body's reference material or materials file) under any theta,
// and its entries of a material gradient are dropped by chain_gradient. Without a mask every
// element is designed, and the layout is the single-body one above with #designed = #T.

#include <Eigen/Core>

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "rbaa/material/material_field.hpp"
#include "rbaa/material/tanh_box_map.hpp"
#include "rbaa/mesh/tet_mesh.hpp"

namespace rbaa {

enum class DesignField { kY = 0, kNu = 1, kRho = 2, kAlpha = 3 };

/// "Y", "nu", "rho", "alpha".
const char* design_field_name(DesignField field);
/// Inverse of design_field_name; throws rbaa::InputError naming the value on an unknown name.
DesignField parse_design_field(const std::string& name);

struct DesignSpaceOptions {
  /// Optimised fields (any order, no duplicates); the layout of theta is always Y, nu, rho, alpha.
  std::vector<DesignField> fields{DesignField::kY, DesignField::kNu, DesignField::kRho,
                                  DesignField::kAlpha};
  double Y_min = 2.5e9, Y_max = 6.5e11;   ///< Pa
  double nu_min = 0.2, nu_max = 0.4;
  double rho_min = 800.0, rho_max = 11300.0;  ///< kg/m^3
  double alpha_min = 1e-3;                    ///< alpha lives in [alpha_min, 1]

  /// Initial values; NaN means the middle of the range (Y, nu).
  double Y0 = std::numeric_limits<double>::quiet_NaN();
  double nu0 = std::numeric_limits<double>::quiet_NaN();
  /// The reference's uniform density: initial rho alpha equals it everywhere (kg/m^3).
  double reference_rho = 2500.0;
  /// Initial interior occupancy when alpha is optimised (rho_0 = reference_rho / alpha0 there).
  double alpha0 = 0.99;

  bool boundary_by_vertex = false;
  /// Vertices whose elements are held solid like boundary elements (occupancy 1, not designed):
  /// a driven body's driven vertices, which the drive holds and which must stay in the object.
  std::vector<int> solid_vertices;
  std::uint64_t seed = 1;
  double perturbation = 0.1;  ///< standard deviation of the Gaussian perturbation of theta_0
};

class DesignSpace {
 public:
  /// Throws rbaa::InputError when an option is out of range (initial values must lie strictly
  /// inside their ranges, since the tanh map reaches the ends only at infinity). `designed`: #T
  /// flags of the elements in the design (empty: every element); at least one must be set.
  DesignSpace(const TetMesh& mesh, const DesignSpaceOptions& options,
              std::vector<char> designed = {});

  const DesignSpaceOptions& options() const { return options_; }
  int num_tets() const { return num_tets_; }
  /// Length of theta.
  int size() const { return size_; }

  bool optimises(DesignField field) const { return offset_[index(field)] >= 0; }
  /// First entry of the field's block in theta, or -1 when the field is not optimised.
  int offset(DesignField field) const { return offset_[index(field)]; }
  /// #designed for Y, nu, rho; #interior for alpha; 0 when not optimised.
  int block_size(DesignField field) const { return block_size_[index(field)]; }
  /// The elements of a field's block in theta, in its order: designed() for Y, nu and rho,
  /// interior() for alpha (whether or not the field is optimised).
  const std::vector<int>& elements(DesignField field) const {
    return field == DesignField::kAlpha ? interior_ : designed_;
  }
  const TanhBoxMap& map(DesignField field) const { return maps_[index(field)]; }

  /// #T flags of the elements whose alpha is fixed at 1 (boundary elements of the whole mesh and
  /// the elements of solid_vertices).
  const std::vector<char>& boundary() const { return boundary_; }
  /// #designed element indices, increasing: entry i of the Y, nu and rho blocks belongs to
  /// designed()[i]. Every element without a mask.
  const std::vector<int>& designed() const { return designed_; }
  int num_designed() const { return static_cast<int>(designed_.size()); }
  /// Whether element e is in the design (#T flags).
  bool is_designed(int e) const { return designed_flag_[e] != 0; }
  /// #interior designed, non-boundary element indices, increasing: entry i of the alpha block
  /// belongs to interior()[i].
  const std::vector<int>& interior() const { return interior_; }
  int num_interior() const { return static_cast<int>(interior_.size()); }

  /// The unperturbed initial material (SPEC section 4): Y0, nu0; alpha = alpha0 on interior
  /// elements when alpha is optimised (else 1) and 1 on boundary elements; rho alpha =
  /// reference_rho everywhere. Fields not in theta keep these values in to_material; elements
  /// outside the mask hold what hold_fixed_elements gave them.
  const MaterialField& initial_material() const { return initial_; }

  /// Makes every element outside the mask keep the values of `field` (#T per array; entries of
  /// designed elements are ignored) in initial_material and in every to_material. Throws
  /// rbaa::InputError on a size mismatch.
  void hold_fixed_elements(const MaterialField& field);

  /// Makes the fields that are not in theta keep the values of `field` (#T per array) instead of
  /// the initial ones, so that one given design can be examined field by field. Throws
  /// rbaa::InputError on a size mismatch.
  void hold_fixed_fields(const MaterialField& field);

  /// theta of initial_material() plus, with perturb, N(0, perturbation^2) per entry drawn from
  /// std::mt19937_64(seed) through a Box-Muller transform in theta's order (the same on every
  /// platform, unlike std::normal_distribution).
  Eigen::VectorXd initial_theta(bool perturb = true) const;

  /// The material field of theta (size()).
  MaterialField to_material(const Eigen::VectorXd& theta) const;

  /// theta of a material field whose optimised values lie strictly inside their ranges (for
  /// restarts); throws rbaa::InputError naming the element otherwise.
  Eigen::VectorXd to_theta(const MaterialField& field) const;

  /// dx/dtheta per entry of theta (size()): the diagonal Jacobian of the box maps.
  Eigen::VectorXd map_derivative(const Eigen::VectorXd& theta) const;

  /// dC/dtheta (size()) from dC/d(material): per entry dC/dx_e dx_e/dtheta_e. Gradients of
  /// fields that are not optimised, of boundary elements' alpha, and of elements outside the
  /// mask are dropped.
  Eigen::VectorXd chain_gradient(const Eigen::VectorXd& theta, const MaterialGradient& g) const;

 private:
  static int index(DesignField f) { return static_cast<int>(f); }
  void check_theta(const Eigen::VectorXd& theta) const;
  void check_field_size(const MaterialField& field) const;

  DesignSpaceOptions options_;
  int num_tets_ = 0;
  int size_ = 0;
  int offset_[4] = {-1, -1, -1, -1};
  int block_size_[4] = {0, 0, 0, 0};
  TanhBoxMap maps_[4];
  std::vector<char> boundary_;
  std::vector<char> designed_flag_;
  std::vector<int> designed_;
  std::vector<int> interior_;
  MaterialField initial_;
};

}  // namespace rbaa
