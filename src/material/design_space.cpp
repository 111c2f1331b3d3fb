#include "rbaa/material/design_space.hpp"

#include <cmath>
#include <random>
#include <sstream>
#include <string>

#include "rbaa/error.hpp"
#include "rbaa/mesh/topology.hpp"

namespace rbaa {

const char* design_field_name(DesignField field) {
  switch (field) {
    case DesignField::kY: return "Y";
    case DesignField::kNu: return "nu";
    case DesignField::kRho: return "rho";
    case DesignField::kAlpha: return "alpha";
  }
  return "?";
}

DesignField parse_design_field(const std::string& name) {
  for (DesignField f : {DesignField::kY, DesignField::kNu, DesignField::kRho, DesignField::kAlpha}) {
    if (name == design_field_name(f)) return f;
  }
  throw InputError("unknown design field '" + name + "' (expected Y, nu, rho or alpha)");
}

namespace {

std::string describe(const std::string& what, double value) {
  std::ostringstream msg;
  msg.precision(17);
  msg << what << " = " << value;
  return msg.str();
}

// Standard normal deviates from raw mt19937_64 output (Box-Muller), so that the perturbation is
// the same with every standard library.
class PortableNormal {
 public:
  explicit PortableNormal(std::uint64_t seed) : engine_(seed) {}
  double operator()() {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    // u1 in (0, 1], u2 in [0, 1), each from the top 53 bits of one draw.
    const double u1 = (static_cast<double>(engine_() >> 11) + 1.0) * 0x1.0p-53;
    const double u2 = static_cast<double>(engine_() >> 11) * 0x1.0p-53;
    const double r = std::sqrt(-2.0 * std::log(u1));
    const double a = 2.0 * M_PI * u2;
    spare_ = r * std::sin(a);
    has_spare_ = true;
    return r * std::cos(a);
  }

 private:
  std::mt19937_64 engine_;
  double spare_ = 0.0;
  bool has_spare_ = false;
};

}  // namespace

DesignSpace::DesignSpace(const TetMesh& mesh, const DesignSpaceOptions& options,
                         std::vector<char> designed)
    : options_(options), num_tets_(mesh.num_tets()), designed_flag_(std::move(designed)) {
  const DesignSpaceOptions& o = options_;
  maps_[index(DesignField::kY)] = TanhBoxMap(o.Y_min, o.Y_max, "Young's modulus range (Pa)");
  maps_[index(DesignField::kNu)] = TanhBoxMap(o.nu_min, o.nu_max, "Poisson's ratio range");
  maps_[index(DesignField::kRho)] = TanhBoxMap(o.rho_min, o.rho_max, "density range (kg/m^3)");
  if (!(o.alpha_min > 0.0 && o.alpha_min < 1.0)) {
    throw InputError(describe("alpha_min", o.alpha_min) + " must lie in (0, 1)");
  }
  maps_[index(DesignField::kAlpha)] = TanhBoxMap(o.alpha_min, 1.0, "occupancy range");
  if (!(o.perturbation >= 0.0 && std::isfinite(o.perturbation))) {
    throw InputError(describe("perturbation", o.perturbation) + " must be finite and >= 0");
  }
  if (!(o.reference_rho > 0.0 && std::isfinite(o.reference_rho))) {
    throw InputError(describe("reference_rho", o.reference_rho) + " must be positive");
  }

  bool chosen[4] = {false, false, false, false};
  for (DesignField f : o.fields) {
    if (chosen[index(f)]) {
      throw InputError(std::string("design field '") + design_field_name(f) + "' listed twice");
    }
    chosen[index(f)] = true;
  }

  if (designed_flag_.empty()) designed_flag_.assign(num_tets_, 1);
  if (static_cast<int>(designed_flag_.size()) != num_tets_) {
    std::ostringstream msg;
    msg << "design space: the element mask has " << designed_flag_.size() << " entries, the mesh "
        << num_tets_ << " elements";
    throw InputError(msg.str());
  }
  boundary_ = boundary_elements(mesh, o.boundary_by_vertex);
  if (!o.solid_vertices.empty()) {
    std::vector<char> solid(mesh.num_vertices(), 0);
    for (int v : o.solid_vertices) {
      if (v < 0 || v >= mesh.num_vertices()) {
        throw InputError("design space: solid vertex " + std::to_string(v) + " is not in the mesh");
      }
      solid[v] = 1;
    }
    for (int e = 0; e < num_tets_; ++e) {
      for (int a = 0; a < 4; ++a) boundary_[e] = boundary_[e] || solid[mesh.T(e, a)];
    }
  }
  for (int e = 0; e < num_tets_; ++e) {
    if (!designed_flag_[e]) continue;
    designed_.push_back(e);
    if (!boundary_[e]) interior_.push_back(e);
  }
  if (designed_.empty()) throw InputError("design space: the element mask selects no element");

  for (int f = 0; f < 4; ++f) {
    if (!chosen[f]) continue;
    offset_[f] = size_;
    block_size_[f] = (f == index(DesignField::kAlpha)) ? num_interior() : num_designed();
    size_ += block_size_[f];
  }

  // Initial material: Y, nu mid-range unless given; rho alpha = reference_rho everywhere.
  const double Y0 = std::isnan(o.Y0) ? map(DesignField::kY).mid() : o.Y0;
  const double nu0 = std::isnan(o.nu0) ? map(DesignField::kNu).mid() : o.nu0;
  const bool with_alpha = optimises(DesignField::kAlpha);
  initial_ = MaterialField::uniform(num_tets_, Y0, nu0, o.reference_rho, 1.0);
  if (with_alpha) {
    map(DesignField::kAlpha).inverse(o.alpha0, "alpha0");
    for (int e : interior_) {
      initial_.alpha[e] = o.alpha0;
      initial_.rho[e] = o.reference_rho / o.alpha0;
    }
  }
  // The initial values of optimised fields must have a finite theta; fixed fields need not lie in
  // the attack's ranges (they are never mapped).
  if (optimises(DesignField::kY)) map(DesignField::kY).inverse(Y0, "initial Y (Pa)");
  if (optimises(DesignField::kNu)) map(DesignField::kNu).inverse(nu0, "initial nu");
  if (optimises(DesignField::kRho)) {
    map(DesignField::kRho).inverse(o.reference_rho, "initial rho (kg/m^3)");
    if (with_alpha) {
      map(DesignField::kRho).inverse(o.reference_rho / o.alpha0, "initial rho = reference_rho / alpha0");
    }
  }
}

void DesignSpace::check_theta(const Eigen::VectorXd& theta) const {
  if (theta.size() != size_) {
    std::ostringstream msg;
    msg << "design vector has " << theta.size() << " entries, the design space " << size_;
    throw InputError(msg.str());
  }
}

Eigen::VectorXd DesignSpace::initial_theta(bool perturb) const {
  Eigen::VectorXd theta = to_theta(initial_);
  if (perturb && options_.perturbation > 0.0) {
    PortableNormal normal(options_.seed);
    for (int i = 0; i < size_; ++i) theta[i] += options_.perturbation * normal();
  }
  return theta;
}

void DesignSpace::check_field_size(const MaterialField& field) const {
  if (field.size() != num_tets_ || field.nu.size() != num_tets_ || field.rho.size() != num_tets_ ||
      field.alpha.size() != num_tets_) {
    std::ostringstream msg;
    msg << "material field does not have " << num_tets_ << " entries per array";
    throw InputError(msg.str());
  }
}

void DesignSpace::hold_fixed_elements(const MaterialField& field) {
  check_field_size(field);
  for (int e = 0; e < num_tets_; ++e) {
    if (designed_flag_[e]) continue;
    initial_.Y[e] = field.Y[e];
    initial_.nu[e] = field.nu[e];
    initial_.rho[e] = field.rho[e];
    initial_.alpha[e] = field.alpha[e];
  }
}

void DesignSpace::hold_fixed_fields(const MaterialField& field) {
  check_field_size(field);
  if (!optimises(DesignField::kY)) initial_.Y = field.Y;
  if (!optimises(DesignField::kNu)) initial_.nu = field.nu;
  if (!optimises(DesignField::kRho)) initial_.rho = field.rho;
  if (!optimises(DesignField::kAlpha)) initial_.alpha = field.alpha;
}

MaterialField DesignSpace::to_material(const Eigen::VectorXd& theta) const {
  check_theta(theta);
  MaterialField m = initial_;
  auto fill = [&](DesignField f, Eigen::VectorXd& out) {
    if (!optimises(f)) return;
    const TanhBoxMap& bm = map(f);
    const int o = offset(f);
    for (int i = 0; i < num_designed(); ++i) out[designed_[i]] = bm.value(theta[o + i]);
  };
  fill(DesignField::kY, m.Y);
  fill(DesignField::kNu, m.nu);
  fill(DesignField::kRho, m.rho);
  if (optimises(DesignField::kAlpha)) {
    const TanhBoxMap& bm = map(DesignField::kAlpha);
    const int o = offset(DesignField::kAlpha);
    for (int i = 0; i < num_interior(); ++i) m.alpha[interior_[i]] = bm.value(theta[o + i]);
  }
  return m;
}

Eigen::VectorXd DesignSpace::to_theta(const MaterialField& field) const {
  check_field_size(field);
  Eigen::VectorXd theta(size_);
  auto take = [&](DesignField f, const Eigen::VectorXd& values) {
    if (!optimises(f)) return;
    const int o = offset(f);
    for (int i = 0; i < num_designed(); ++i) {
      const int e = designed_[i];
      theta[o + i] = map(f).inverse(
          values[e], std::string(design_field_name(f)) + " of element " + std::to_string(e));
    }
  };
  take(DesignField::kY, field.Y);
  take(DesignField::kNu, field.nu);
  take(DesignField::kRho, field.rho);
  if (optimises(DesignField::kAlpha)) {
    const int o = offset(DesignField::kAlpha);
    for (int i = 0; i < num_interior(); ++i) {
      const int e = interior_[i];
      theta[o + i] =
          map(DesignField::kAlpha).inverse(field.alpha[e], "alpha of element " + std::to_string(e));
    }
  }
  return theta;
}

Eigen::VectorXd DesignSpace::map_derivative(const Eigen::VectorXd& theta) const {
  check_theta(theta);
  Eigen::VectorXd d(size_);
  for (int f = 0; f < 4; ++f) {
    if (offset_[f] < 0) continue;
    for (int i = 0; i < block_size_[f]; ++i) d[offset_[f] + i] = maps_[f].derivative(theta[offset_[f] + i]);
  }
  return d;
}

Eigen::VectorXd DesignSpace::chain_gradient(const Eigen::VectorXd& theta,
                                            const MaterialGradient& g) const {
  check_theta(theta);
  Eigen::VectorXd out = Eigen::VectorXd::Zero(size_);
  auto check_size = [&](const Eigen::VectorXd& v, DesignField f) {
    if (v.size() != 0 && v.size() != num_tets_) {
      std::ostringstream msg;
      msg << "material gradient d/d" << design_field_name(f) << " has " << v.size()
          << " entries, the mesh " << num_tets_ << " elements";
      throw InputError(msg.str());
    }
    return v.size() != 0 && optimises(f);
  };
  auto per_element = [&](DesignField f, const Eigen::VectorXd& v) {
    if (!check_size(v, f)) return;
    const int o = offset(f);
    for (int i = 0; i < num_designed(); ++i) {
      out[o + i] = v[designed_[i]] * map(f).derivative(theta[o + i]);
    }
  };
  per_element(DesignField::kY, g.Y);
  per_element(DesignField::kNu, g.nu);
  per_element(DesignField::kRho, g.rho);
  if (check_size(g.alpha, DesignField::kAlpha)) {
    const int o = offset(DesignField::kAlpha);
    for (int i = 0; i < num_interior(); ++i) {
      out[o + i] = g.alpha[interior_[i]] * map(DesignField::kAlpha).derivative(theta[o + i]);
    }
  }
  return out;
}

}  // namespace rbaa
