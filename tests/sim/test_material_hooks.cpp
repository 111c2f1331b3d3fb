// The forms' material hooks (form.hpp): add_material_tangent against central differences of the
// forms' gradients rebuilt with perturbed materials, field by field, and add_material_adjoint as
// its transpose (a^T (dG/dtheta) d = -<g, d>). The adjoint and the tangent-linear pass sum these
// hooks over the forms, so an error here is an error in every material gradient.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <memory>
#include <random>

#include "mesh_fixtures.hpp"
#include "rbaa/sim/elastic_form.hpp"
#include "rbaa/sim/gravity_form.hpp"
#include "rbaa/sim/inertia_form.hpp"
#include "rbaa/sim/mass_matrix.hpp"

namespace rbaa {
namespace {

MaterialField varied_materials(int nt, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  MaterialField m = MaterialField::uniform(nt, 1e10, 0.3, 2500.0);
  for (int e = 0; e < nt; ++e) {
    m.Y[e] = 2.5e9 + u(rng) * 6.5e11;
    m.nu[e] = 0.2 + 0.2 * u(rng);
    m.rho[e] = 800 + 10000 * u(rng);
    m.alpha[e] = 0.3 + 0.7 * u(rng);
  }
  return m;
}

Eigen::VectorXd random_vector(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  Eigen::VectorXd v(n);
  for (int i = 0; i < n; ++i) v[i] = g(rng);
  return v;
}

// A direction along one field only, relative to the field's values.
MaterialGradient direction_along(int field, const MaterialField& m, unsigned seed) {
  MaterialGradient d;
  const Eigen::VectorXd r = random_vector(m.size(), seed);
  if (field == 0) d.Y = m.Y.cwiseProduct(r);
  if (field == 1) d.nu = 0.1 * m.nu.cwiseProduct(r);
  if (field == 2) d.rho = m.rho.cwiseProduct(r);
  if (field == 3) d.alpha = 0.1 * m.alpha.cwiseProduct(r);
  return d;
}

MaterialField moved(MaterialField m, const MaterialGradient& d, double s) {
  if (d.Y.size()) m.Y += s * d.Y;
  if (d.nu.size()) m.nu += s * d.nu;
  if (d.rho.size()) m.rho += s * d.rho;
  if (d.alpha.size()) m.alpha += s * d.alpha;
  return m;
}

double dot(const MaterialGradient& g, const MaterialGradient& d) {
  double s = 0;
  if (d.Y.size()) s += g.Y.dot(d.Y);
  if (d.nu.size()) s += g.nu.dot(d.nu);
  if (d.rho.size()) s += g.rho.dot(d.rho);
  if (d.alpha.size()) s += g.alpha.dot(d.alpha);
  return s;
}

using FormFactory = std::function<std::unique_ptr<Form>(const MaterialField&)>;

// Checks one form's hooks along every field; returns the worst relative errors.
void check_hooks(const char* name, const FormFactory& make, const MaterialField& m,
                 const Eigen::VectorXd& x, const Eigen::VectorXd& a, double scale) {
  const char* fields[] = {"Y", "nu", "rho", "alpha"};
  const std::unique_ptr<Form> form = make(m);
  MaterialGradient g;
  const int nt = m.size();
  g.Y = g.nu = g.rho = g.alpha = Eigen::VectorXd::Zero(nt);
  form->add_material_adjoint(x, a, scale, m, g);
  for (int f = 0; f < 4; ++f) {
    const MaterialGradient d = direction_along(f, m, 10 + f);
    Eigen::VectorXd tangent = Eigen::VectorXd::Zero(x.size());
    form->add_material_tangent(x, d, scale, m, tangent);
    const double s = 1e-5;
    Eigen::VectorXd plus = Eigen::VectorXd::Zero(x.size()), minus = plus;
    make(moved(m, d, s))->add_gradient(x, scale, plus);
    make(moved(m, d, -s))->add_gradient(x, scale, minus);
    const Eigen::VectorXd fd = (plus - minus) / (2 * s);
    const double reference = std::max(fd.norm(), tangent.norm());
    const double fd_error = reference == 0 ? 0.0 : (tangent - fd).norm() / reference;
    // The adjoint hook is the tangent hook's transpose with the adjoint's sign.
    const double at = a.dot(tangent), gd = dot(g, d);
    const double transpose_error = std::abs(at + gd) / std::max(std::abs(at), 1e-300);
    std::printf("%-8s %-5s |dG| %.3e  FD error %.2e  transpose error %.2e\n", name, fields[f],
                tangent.norm(), fd_error, transpose_error);
    EXPECT_LE(fd_error, 1e-7) << name << " " << fields[f];
    EXPECT_LE(transpose_error, 1e-12) << name << " " << fields[f];
  }
}

TEST(MaterialHooks, TangentMatchesDifferencesAndAdjointIsItsTranspose) {
  const TetMesh mesh = test::ball_mesh(0.1, 2);
  const MaterialField m = varied_materials(mesh.num_tets(), 3);
  const Eigen::VectorXd x = test::deformed(mesh, 0.01, 4);
  const Eigen::VectorXd q_hat = test::deformed(mesh, 0.01, 5);
  const Eigen::VectorXd a = random_vector(x.size(), 6);
  const double w = 4.0 / 9.0 * 1e-4;  // BDF-2's weight at h = 0.01

  check_hooks("elastic", [&](const MaterialField& f) {
    return std::make_unique<ElasticForm>(mesh, f);
  }, m, x, a, w);
  for (MassModel model : {MassModel::kConsistent, MassModel::kLumped}) {
    SparseHessian H(mesh.T, mesh.num_vertices());
    check_hooks(model == MassModel::kConsistent ? "inertia" : "inertiaL", [&](const MaterialField& f) {
      auto form = std::make_unique<InertiaForm>(mass_matrix(mesh, f.effective_density(), model, H),
                                                UnitElementMass(mesh, model));
      form->set_predictor(q_hat);
      return form;
    }, m, x, a, 1.0);
    check_hooks(model == MassModel::kConsistent ? "gravity" : "gravityL", [&](const MaterialField& f) {
      return std::make_unique<GravityForm>(vertex_masses(mesh, f.effective_density()),
                                           Eigen::Vector3d(0.3, -0.2, -9.81),
                                           UnitElementMass(mesh, model));
    }, m, x, a, w);
  }
}

}  // namespace
}  // namespace rbaa
