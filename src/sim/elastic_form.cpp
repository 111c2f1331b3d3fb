#include "rbaa/sim/elastic_form.hpp"

#include <Eigen/Dense>
#include <omp.h>

#include <cmath>

#include "rbaa/material/lame.hpp"
#include "rbaa/sim/parallel.hpp"
#include "rbaa/sim/stable_neo_hookean.hpp"

namespace rbaa {

ElasticForm::ElasticForm(const TetMesh& rest, const MaterialField& materials) : tets_(rest.T) {
  const RestShape shape = compute_rest_shape(rest);
  const int nt = rest.num_tets();
  B_.resize(nt);
  for (int e = 0; e < nt; ++e) {
    // F = Ds Dm^-1 = sum_{k=1..3} (x_k - x_0) row_{k-1}(Dm^-1): b_k = row, b_0 = -sum.
    const Eigen::Matrix3d& Di = shape.Dm_inv[e];
    B_[e].block<3, 3>(0, 1) = Di.transpose();
    B_[e].col(0) = -Di.transpose().rowwise().sum();
  }
  volume_ = shape.volume;
  set_materials(materials);
  // Vertex -> (element, local vertex) incidence, ordered by element, for the gradient gather.
  const int nv = rest.num_vertices();
  incidence_start_.assign(nv + 1, 0);
  for (int e = 0; e < nt; ++e) {
    for (int a = 0; a < 4; ++a) ++incidence_start_[tets_(e, a) + 1];
  }
  for (int v = 0; v < nv; ++v) incidence_start_[v + 1] += incidence_start_[v];
  incidence_.resize(4 * std::size_t(nt));
  std::vector<int> pos(incidence_start_.begin(), incidence_start_.end() - 1);
  for (int e = 0; e < nt; ++e) {
    for (int a = 0; a < 4; ++a) incidence_[pos[tets_(e, a)]++] = 4 * e + a;
  }
  element_buffer_.assign(12 * std::size_t(nt), 0.0);
}

void ElasticForm::set_materials(const MaterialField& materials) {
  const int nt = num_elements();
  mu_.resize(nt);
  lambda_.resize(nt);
  weight_.resize(nt);
  for (int e = 0; e < nt; ++e) {
    const LameParameters lame = lame_from_young_poisson(materials.Y[e], materials.nu[e]);
    mu_[e] = lame.mu;
    lambda_[e] = lame.lambda;
    const double a = materials.alpha[e];
    weight_[e] = a * a * a * volume_[e];
  }
}

Eigen::Matrix3d ElasticForm::deformation_gradient(const Eigen::VectorXd& q, int e) const {
  // F(i, j) = sum_a x_a(i) B(j, a), summed over a in order from zero: the same products and sums
  // as F += x_a b_a^T, written out because Eigen compiled that loop into stores of two doubles
  // re-read across their halves (a store-forwarding stall each), which made this gather ~5 % of
  // an attack iteration (energies, gradients and Hessians all start here).
  const double* x[4];
  for (int a = 0; a < 4; ++a) x[a] = q.data() + 3 * std::ptrdiff_t(tets_(e, a));
  const double* B = B_[e].data();  // column-major: B(j, a) at j + 3 a
  Eigen::Matrix3d F;
  for (int j = 0; j < 3; ++j) {
    for (int i = 0; i < 3; ++i) {
      double f = 0.0;
      for (int a = 0; a < 4; ++a) f += x[a][i] * B[j + 3 * a];
      F(i, j) = f;
    }
  }
  return F;
}

double ElasticForm::value(const Eigen::VectorXd& q) const {
  const int nt = num_elements();
  double* buf = element_buffer_.data();
#pragma omp parallel for schedule(static) if (nt > kParallelCheapElements)
  for (int e = 0; e < nt; ++e) {
    const snh::EnergyParts p = snh::energy_parts(deformation_gradient(q, e));
    buf[e] = weight_[e] * (mu_[e] * p.mu + lambda_[e] * p.lambda);
  }
  double sum = 0;  // fixed order
  for (int e = 0; e < nt; ++e) sum += buf[e];
  return sum;
}

double ElasticForm::value_difference(const Eigen::VectorXd& q0, const Eigen::VectorXd& q1) const {
  const int nt = num_elements();
  double* buf = element_buffer_.data();
  const Eigen::VectorXd dq = q1 - q0;
#pragma omp parallel for schedule(static) if (nt > kParallelCheapElements)
  for (int e = 0; e < nt; ++e) {
    const snh::EnergyParts p =
        snh::energy_parts_difference(deformation_gradient(q0, e), deformation_gradient(dq, e));
    buf[e] = weight_[e] * (mu_[e] * p.mu + lambda_[e] * p.lambda);
  }
  double sum = 0;
  for (int e = 0; e < nt; ++e) sum += buf[e];
  return sum;
}

void ElasticForm::add_gradient(const Eigen::VectorXd& q, double scale, Eigen::VectorXd& grad) const {
  const int nt = num_elements();
  double* buf = element_buffer_.data();
#pragma omp parallel for schedule(static) if (nt > kParallelCheapElements)
  for (int e = 0; e < nt; ++e) {
    const Eigen::Matrix3d P = weight_[e] * snh::stress(deformation_gradient(q, e), mu_[e], lambda_[e]);
    // dPsi/dx_a = P b_a
    Eigen::Map<Eigen::Matrix<double, 3, 4>>(buf + 12 * std::size_t(e)) = P * B_[e];
  }
  const int nv = static_cast<int>(incidence_start_.size()) - 1;
  Eigen::VectorXd& f = vertex_buffer_;
  f.resize(3 * nv);
#pragma omp parallel for schedule(static) if (nv > kParallelVertices)
  for (int v = 0; v < nv; ++v) {
    Eigen::Vector3d g = Eigen::Vector3d::Zero();
    for (int s = incidence_start_[v]; s < incidence_start_[v + 1]; ++s) {
      g += Eigen::Map<const Eigen::Vector3d>(buf + 3 * std::size_t(incidence_[s]));
    }
    f.segment<3>(3 * v) = g;
  }
  // Elastic forces are internal: their sum and their torque vanish exactly (Psi is invariant under
  // translations and rotations), but in floating point each is left with the round-off of
  // thousands of element forces of a Y = 1e13 body. Only the body's mass resists those six rigid
  // directions, so Newton's step kept a rigid drift of ~1e-12 m per step that no iteration
  // removes (the ball at newton.tolerance 1e-10 stopped 8 steps at a round-off floor of 8.9e-11
  // m/s, grinding 8-26 iterations a step). Removing the net force and torque (the least change
  // a + b x r_i, uniform weights about the vertices' centroid) changes the gradient by round-off
  // only, and its derivative, the Hessian, not at all.
  Eigen::Vector3d c = Eigen::Vector3d::Zero(), F = Eigen::Vector3d::Zero(), T = Eigen::Vector3d::Zero();
  for (int v = 0; v < nv; ++v) c += q.segment<3>(3 * v);
  c /= nv;
  Eigen::Matrix3d I = Eigen::Matrix3d::Zero();
  for (int v = 0; v < nv; ++v) {
    const Eigen::Vector3d r = q.segment<3>(3 * v) - c;
    F += f.segment<3>(3 * v);
    T += r.cross(f.segment<3>(3 * v));
    I += r.squaredNorm() * Eigen::Matrix3d::Identity() - r * r.transpose();
  }
  const Eigen::Vector3d a = F / nv;
  Eigen::Vector3d b = I.ldlt().solve(T);
  if (!b.allFinite()) b.setZero();  // fewer than three non-collinear vertices: no torque to fix
#pragma omp parallel for schedule(static) if (nv > kParallelVertices)
  for (int v = 0; v < nv; ++v) {
    const Eigen::Vector3d r = q.segment<3>(3 * v) - c;
    grad.segment<3>(3 * v) += scale * (f.segment<3>(3 * v) - a - b.cross(r));
  }
}

namespace {

// H += w D^T H9 D, D = dvec(F)/dx the 9x12 map of dF = sum_a dx_a b_a^T (vec column-major:
// F(i, j) at i + 3 j; local dof 3 a + i), into the packed lower 12x12 block. With B(j, a) = (b_a)_j:
// H12(3a+i, 3b+k) = sum_{j,l} B(j, a) B(l, b) H9(i+3j, k+3l), in two passes (~560 products).
// With kAssign the block is H = w D^T H9 D instead (SparseHessian::element_block_for_writing).
template <bool kAssign>
void add_pulled_back(const Eigen::Matrix<double, 9, 9>& H9, const Eigen::Matrix<double, 3, 4>& B,
                     double w, double* H) {
  Eigen::Matrix<double, 9, 12> T;  // T(r, 3b+k) = sum_l H9(r, k+3l) B(l, b)
  for (int b = 0; b < 4; ++b) {
    for (int k = 0; k < 3; ++k) {
      T.col(3 * b + k) = H9.col(k) * B(0, b) + H9.col(k + 3) * B(1, b) + H9.col(k + 6) * B(2, b);
    }
  }
  int p = 0;
  for (int c = 0; c < 12; ++c) {
    for (int r = c; r < 12; ++r) {
      const int a = r / 3, i = r % 3;
      const double h = w * (B(0, a) * T(i, c) + B(1, a) * T(i + 3, c) + B(2, a) * T(i + 6, c));
      H[p] = kAssign ? h : H[p] + h;
      ++p;
    }
  }
}

// The exact Hessian's block in closed form, H = w D^T H9 D for H9 = mu I + lambda g g^T + s d2J/dF2
// (snh::hessian; g = vec C, C the cofactor of F, s = lambda (J - 1) - mu), block by block:
//   H12_ab = w [mu (b_a . b_b) I + lambda v_a v_b^T - s [F (b_a x b_b)]_x],  v_a = C b_a,
// because D^T D = (B^T B) (x) I, D^T g = vec(C B), and sum_{j,l} B(j, a) B(l, b) d2J/(df_j df_l)
// = -[F (b_a x b_b)]_x (the second derivatives of det F are cross matrices of F's columns). The
// same matrix as forming H9 and pulling it back (add_pulled_back) up to round-off, in less than
// half the time: the ball's exact elastic Hessian 5.2 -> 2.3 ms (bench_assembly).
template <bool kAssign>
void add_exact_block(const Eigen::Matrix3d& F, double mu, double lambda,
                     const Eigen::Matrix<double, 3, 4>& B, double w, double* H) {
  const Eigen::Matrix3d C = snh::cofactor(F);
  const double J = F.col(0).dot(C.col(0));
  const double s = w * (lambda * (J - 1.0) - mu);
  const Eigen::Matrix<double, 3, 4> V = C * B;
  // The whole 12x12 block, branch-free: the rank-one lambda part, then the mu and det parts per
  // vertex pair (b_a x b_b = 0 on the diagonal blocks, and the upper blocks are never read).
  const Eigen::Matrix<double, 12, 1> v = Eigen::Map<const Eigen::Matrix<double, 12, 1>>(V.data());
  Eigen::Matrix<double, 12, 12> K = ((w * lambda) * v) * v.transpose();
  for (int b = 0; b < 4; ++b) {
    for (int a = b; a < 4; ++a) {
      K.block<3, 3>(3 * a, 3 * b).diagonal().array() += w * mu * B.col(a).dot(B.col(b));
      if (a == b) continue;
      const Eigen::Vector3d u = s * (F * B.col(a).cross(B.col(b)));
      // - [u]_x
      K(3 * a + 0, 3 * b + 1) += u.z();
      K(3 * a + 0, 3 * b + 2) -= u.y();
      K(3 * a + 1, 3 * b + 0) -= u.z();
      K(3 * a + 1, 3 * b + 2) += u.x();
      K(3 * a + 2, 3 * b + 0) += u.y();
      K(3 * a + 2, 3 * b + 1) -= u.x();
    }
  }
  int p = 0;
  for (int c = 0; c < 12; ++c) {
    for (int r = c; r < 12; ++r) {
      H[p] = kAssign ? K(r, c) : H[p] + K(r, c);
      ++p;
    }
  }
}

}  // namespace

void ElasticForm::add_hessian(const Eigen::VectorXd& q, double scale, HessianKind kind,
                              SparseHessian& hessian) const {
  const int nt = num_elements();
  const bool project = kind == HessianKind::kProjected;
  // The rotation modes of an unstrained element sit at +-1e-16 mu: clamping those changes nothing
  // and does not count as a projection (the adjoint may then reuse Newton's factor).
  bool clamped = false;
  // Element e's block, H = w D^T H9 D (assign) or H += it; true when the projection removed a
  // mode.
  auto element = [&](int e, bool assign, double* H) {
    const Eigen::Matrix3d F = deformation_gradient(q, e);
    const double w = scale * weight_[e];
    if (!project) {
      if (assign) {
        add_exact_block<true>(F, mu_[e], lambda_[e], B_[e], w, H);
      } else {
        add_exact_block<false>(F, mu_[e], lambda_[e], B_[e], w, H);
      }
      return false;
    }
    // Any mode the projection removed (below -1e-12 (mu + lambda), see projected_hessian) makes
    // this Hessian differ from the exact one. The removal and this flag once used different
    // thresholds (-1e-14 and -1e-12): modes in between were removed unflagged, Newton labelled
    // such factors exact, and the adjoint reusing them disagreed with the tangent by 1e-7 on the
    // cube once a rigid predictor let contact steps converge on their first, projected, Hessian.
    Eigen::Matrix<double, 9, 9> H9;
    const bool removed = snh::projected_hessian(F, mu_[e], lambda_[e], H9) < 0;
    if (assign) {
      add_pulled_back<true>(H9, B_[e], w, H);
    } else {
      add_pulled_back<false>(H9, B_[e], w, H);
    }
    return removed;
  };
#pragma omp parallel reduction(|| : clamped) if (nt > kParallelElements)
  {
    if (omp_get_num_threads() == 1 && hessian.begin_elements_in_order()) {
      // One thread: each block goes from the stack straight into the matrix's sums (same
      // matrix; the 6 MB element buffer is neither written nor gathered).
      double H[SparseHessian::kPacked];
      for (int e = 0; e < nt; ++e) {
        if (element(e, true, H)) clamped = true;
        hessian.add_element_in_order(e, H);
      }
    } else {
#pragma omp for schedule(static)
      for (int e = 0; e < nt; ++e) {
        double* H = nullptr;
        const bool assign = hessian.element_block_for_writing(e, H);
        if (element(e, assign, H)) clamped = true;
      }
    }
  }
  if (clamped) hessian.mark_projection_active();
}

void ElasticForm::element_gradient_parts(const Eigen::VectorXd& q, int e,
                                         Eigen::Matrix<double, 12, 1>& g_mu,
                                         Eigen::Matrix<double, 12, 1>& g_lambda) const {
  const Eigen::Matrix3d F = deformation_gradient(q, e);
  Eigen::Map<Eigen::Matrix<double, 3, 4>>(g_mu.data()) = weight_[e] * snh::stress_mu(F) * B_[e];
  Eigen::Map<Eigen::Matrix<double, 3, 4>>(g_lambda.data()) =
      weight_[e] * snh::stress_lambda(F) * B_[e];
}

void ElasticForm::add_material_adjoint(const Eigen::VectorXd& x, const Eigen::VectorXd& a,
                                       double scale, const MaterialField& materials,
                                       MaterialGradient& g) const {
  const int nt = num_elements();
#pragma omp parallel for schedule(static) if (nt > kParallelCheapElements)
  for (int e = 0; e < nt; ++e) {
    Eigen::Matrix<double, 12, 1> g_mu, g_lambda, ae;
    for (int i = 0; i < 4; ++i) ae.segment<3>(3 * i) = a.segment<3>(3 * tets_(e, i));
    element_gradient_parts(x, e, g_mu, g_lambda);
    const double p_mu = ae.dot(g_mu), p_lambda = ae.dot(g_lambda);
    const LameDerivatives d = lame_derivatives(materials.Y[e], materials.nu[e]);
    g.Y[e] -= scale * (d.dmu_dY * p_mu + d.dlambda_dY * p_lambda);
    g.nu[e] -= scale * (d.dmu_dnu * p_mu + d.dlambda_dnu * p_lambda);
    // d(alpha^3 mu) / d alpha = 3 alpha^2 mu: the parts already hold alpha^3.
    g.alpha[e] -= scale * 3.0 / materials.alpha[e] * (mu_[e] * p_mu + lambda_[e] * p_lambda);
  }
}

void ElasticForm::add_material_tangent(const Eigen::VectorXd& x, const MaterialGradient& direction,
                                       double scale, const MaterialField& materials,
                                       Eigen::VectorXd& out) const {
  if (direction.Y.size() == 0 && direction.nu.size() == 0 && direction.alpha.size() == 0) return;
  auto entry = [](const Eigen::VectorXd& field, int e) { return field.size() == 0 ? 0.0 : field[e]; };
  for (int e = 0; e < num_elements(); ++e) {
    const double dY = entry(direction.Y, e), dnu = entry(direction.nu, e),
                 dalpha = entry(direction.alpha, e);
    if (dY == 0.0 && dnu == 0.0 && dalpha == 0.0) continue;
    const LameDerivatives l = lame_derivatives(materials.Y[e], materials.nu[e]);
    // d(alpha^3 mu) / alpha^3 = dmu + 3 mu dalpha / alpha, likewise lambda.
    const double dmu = l.dmu_dY * dY + l.dmu_dnu * dnu + 3.0 * mu_[e] * dalpha / materials.alpha[e];
    const double dlambda =
        l.dlambda_dY * dY + l.dlambda_dnu * dnu + 3.0 * lambda_[e] * dalpha / materials.alpha[e];
    if (dmu == 0.0 && dlambda == 0.0) continue;
    Eigen::Matrix<double, 12, 1> g_mu, g_lambda;
    element_gradient_parts(x, e, g_mu, g_lambda);
    const Eigen::Matrix<double, 12, 1> ge = scale * (dmu * g_mu + dlambda * g_lambda);
    for (int i = 0; i < 4; ++i) out.segment<3>(3 * tets_(e, i)) += ge.segment<3>(3 * i);
  }
}

}  // namespace rbaa
