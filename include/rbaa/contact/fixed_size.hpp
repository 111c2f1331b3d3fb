#pragma once
// Fixed-size Eigen types for the contact primitives: a pair of up to four 3D points has 6, 9 or 12
// degrees of freedom, stacked point after point in the order the function's arguments name them.

#include <Eigen/Core>

namespace rbaa::contact {

using Vector6d = Eigen::Matrix<double, 6, 1>;
using Vector9d = Eigen::Matrix<double, 9, 1>;
using Vector12d = Eigen::Matrix<double, 12, 1>;
using Matrix6d = Eigen::Matrix<double, 6, 6>;
using Matrix9d = Eigen::Matrix<double, 9, 9>;
using Matrix12d = Eigen::Matrix<double, 12, 12>;

}  // namespace rbaa::contact
