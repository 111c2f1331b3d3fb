#include "rbaa/material/material_field.hpp"

#include <cmath>
#include <limits>
#include <sstream>

#include "rbaa/error.hpp"

namespace rbaa {

MaterialField MaterialField::uniform(int num_tets, double Y, double nu, double rho, double alpha) {
  MaterialField f;
  f.Y = Eigen::VectorXd::Constant(num_tets, Y);
  f.nu = Eigen::VectorXd::Constant(num_tets, nu);
  f.rho = Eigen::VectorXd::Constant(num_tets, rho);
  f.alpha = Eigen::VectorXd::Constant(num_tets, alpha);
  return f;
}

namespace {

// Every value must lie in the interval from lo to hi, each end open or closed; the message prints
// that interval as it is checked.
void check_field(const Eigen::VectorXd& v, const char* name, int num_tets, double lo, double hi,
                 bool lo_open, bool hi_open, const std::string& source) {
  if (v.size() != num_tets) {
    std::ostringstream msg;
    msg << source << ": material field '" << name << "' has " << v.size()
        << " entries but the mesh has " << num_tets << " tetrahedra";
    throw InputError(msg.str());
  }
  for (int e = 0; e < num_tets; ++e) {
    const double x = v[e];
    const bool ok =
        std::isfinite(x) && (lo_open ? x > lo : x >= lo) && (hi_open ? x < hi : x <= hi);
    if (!ok) {
      std::ostringstream msg;
      msg << source << ": material field '" << name << "' of element " << e << " is " << x
          << ", outside " << (lo_open ? "(" : "[") << lo << ", " << hi << (hi_open ? ")" : "]");
      throw InputError(msg.str());
    }
  }
}

}  // namespace

void validate_material_field(const MaterialField& field, int num_tets, const std::string& source) {
  const double inf = std::numeric_limits<double>::infinity();
  check_field(field.Y, "Y", num_tets, 0.0, inf, true, true, source);
  // nu = 0.5 makes lambda = Y nu / ((1 + nu)(1 - 2 nu)) infinite; nu = -1 makes mu infinite.
  check_field(field.nu, "nu", num_tets, -1.0, 0.5, true, true, source);
  check_field(field.rho, "rho", num_tets, 0.0, inf, true, true, source);
  check_field(field.alpha, "alpha", num_tets, 0.0, 1.0, true, false, source);
}

}  // namespace rbaa
