#pragma once
// Private to the module: places the derivatives of a sub-pair (two or three of a pair's points)
// into the pair's full vector and matrix. blocks[i] is the point index, in the full pair, of the
// sub-pair's i-th point.

#include <Eigen/Core>
#include <array>

namespace rbaa::contact::detail {

template <int N, int M>
Eigen::Matrix<double, 3 * M, 1> scatter(const Eigen::Matrix<double, 3 * N, 1>& g,
                                        const std::array<int, N>& blocks) {
  Eigen::Matrix<double, 3 * M, 1> out = Eigen::Matrix<double, 3 * M, 1>::Zero();
  for (int i = 0; i < N; ++i) out.template segment<3>(3 * blocks[i]) = g.template segment<3>(3 * i);
  return out;
}

template <int N, int M>
Eigen::Matrix<double, 3 * M, 3 * M> scatter(const Eigen::Matrix<double, 3 * N, 3 * N>& H,
                                            const std::array<int, N>& blocks) {
  Eigen::Matrix<double, 3 * M, 3 * M> out = Eigen::Matrix<double, 3 * M, 3 * M>::Zero();
  for (int i = 0; i < N; ++i)
    for (int j = 0; j < N; ++j)
      out.template block<3, 3>(3 * blocks[i], 3 * blocks[j]) = H.template block<3, 3>(3 * i, 3 * j);
  return out;
}

}  // namespace rbaa::contact::detail
