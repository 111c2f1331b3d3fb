#pragma once
// IPC's C1 smoothing of Coulomb friction's |u| (Li et al. 2020, section 5.2), with eps = eps_v tau
// (m): the friction potential of a pair is mu lambda f0(|u|) with
//
//   f1(y) = 2 y / eps - y^2 / eps^2 (y < eps), 1 (y >= eps);   f0' = f1, f0(eps) = eps,
//   f0(y) = -y^3 / (3 eps^2) + y^2 / eps + eps / 3 (y < eps), y (y >= eps),
//
// so that the force mu lambda f1(|u|) u / |u| is Coulomb's mu lambda above eps and vanishes
// linearly below. The derivatives a form needs, as functions of the tangential displacement u
// (2 or 3 components), are grad f0(|u|) = (f1(y) / y) u and
// hess f0(|u|) = c1(y) u u^T + (f1(y) / y) I with c1 = (f1'(y) y - f1(y)) / y^3, both finite at
// y = 0 (f1 / y -> 2 / eps, c1 u u^T -> 0); that Hessian is PSD (f0(|u|) is convex).

namespace rbaa::contact {

/// f0(y) for y >= 0.
double smooth_friction_f0(double y, double eps);
/// f1(y) / y (2 / eps at y = 0).
double smooth_friction_f1_over_y(double y, double eps);
/// c1(y) = (f1'(y) y - f1(y)) / y^3 (0 at y = 0, where it multiplies u u^T = 0).
double smooth_friction_c1(double y, double eps);
/// f0(y1) - f0(y0) given dy = y1 - y0 computed without cancellation (e.g. from the displacements'
/// difference), factored through dy where both lie on one branch.
double smooth_friction_f0_difference(double y0, double y1, double dy, double eps);

}  // namespace rbaa::contact
