#include "rbaa/sim/sparse_hessian.hpp"

#include <algorithm>
#include <atomic>
#include <cstring>
#include <stdexcept>
#include <string>
#include <utility>

#include "rbaa/sim/parallel.hpp"

namespace rbaa {

namespace {
std::atomic<std::uint64_t> next_pattern_version{1};
}

SparseHessian::SparseHessian(const Tets& tets, int num_vertices)
    : num_elements_(static_cast<int>(tets.rows())), num_vertices_(num_vertices) {
  pattern_version_ = next_pattern_version++;
  const int n = 3 * num_vertices;

  // Block pattern: for each column vertex c, the sorted row vertices r >= c sharing a tet.
  std::vector<std::vector<int>> neighbours(num_vertices);
  for (int v = 0; v < num_vertices; ++v) neighbours[v].push_back(v);
  for (int e = 0; e < num_elements_; ++e) {
    for (int a = 0; a < 4; ++a) {
      for (int b = 0; b < 4; ++b) {
        const int va = tets(e, a), vb = tets(e, b);
        if (va > vb) neighbours[vb].push_back(va);
      }
    }
  }
  std::vector<int> outer(n + 1, 0);
  std::vector<int> inner;
  for (int c = 0; c < num_vertices; ++c) {
    auto& list = neighbours[c];
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
    for (int j = 0; j < 3; ++j) {
      const int col = 3 * c + j;
      for (int i = j; i < 3; ++i) inner.push_back(3 * c + i);  // diagonal block, lower part
      for (std::size_t k = 1; k < list.size(); ++k) {
        for (int i = 0; i < 3; ++i) inner.push_back(3 * list[k] + i);
      }
      outer[col + 1] = static_cast<int>(inner.size());
    }
  }
  const int nnz = static_cast<int>(inner.size());
  std::vector<double> zeros(nnz, 0.0);
  matrix_ = Eigen::Map<const Eigen::SparseMatrix<double>>(n, n, nnz, outer.data(), inner.data(),
                                                          zeros.data());
  matrix_.makeCompressed();
  base_position_.resize(nnz);
  for (int k = 0; k < nnz; ++k) base_position_[k] = k;

  auto entry = [&](int row, int col) {
    const int* begin = inner.data() + outer[col];
    const int* end = inner.data() + outer[col + 1];
    return static_cast<int>(std::lower_bound(begin, end, row) - inner.data());
  };

  // Gather lists: nonzero k <- element entries, counted then filled in element order.
  std::vector<int> target(std::size_t(num_elements_) * kPacked);
  std::vector<int> count(nnz + 1, 0);
  for (int e = 0; e < num_elements_; ++e) {
    for (int c = 0; c < 12; ++c) {
      for (int r = c; r < 12; ++r) {
        int R = 3 * tets(e, r / 3) + r % 3, C = 3 * tets(e, c / 3) + c % 3;
        if (R < C) std::swap(R, C);  // the block is symmetric
        const int k = entry(R, C);
        target[std::size_t(e) * kPacked + packed_index(r, c)] = k;
        ++count[k + 1];
      }
    }
  }
  element_target_ = target;
  source_start_.assign(nnz + 1, 0);
  for (int k = 0; k < nnz; ++k) source_start_[k + 1] = source_start_[k] + count[k + 1];
  sources_.resize(source_start_[nnz]);
  std::vector<int> fill(source_start_.begin(), source_start_.end() - 1);
  for (std::size_t s = 0; s < target.size(); ++s) sources_[fill[target[s]]++] = static_cast<int>(s);

  diagonal_entries_.resize(6 * std::size_t(num_vertices));
  for (int v = 0; v < num_vertices; ++v) {
    int p = 0;
    for (int j = 0; j < 3; ++j) {
      for (int i = j; i < 3; ++i) diagonal_entries_[6 * v + p++] = entry(3 * v + i, 3 * v + j);
    }
  }

  element_values_.assign(std::size_t(num_elements_) * kPacked, 0.0);
  element_generation_.assign(num_elements_, generation_);  // zero, as filled
  vertex_values_.assign(num_vertices, Eigen::Matrix3d::Zero());
  vertex_touched_.assign(num_vertices, 0);
  direct_ = Eigen::VectorXd::Zero(nnz);
  base_outer_ = std::move(outer);
  base_inner_ = std::move(inner);
}

int SparseHessian::base_entry(int row, int col) const {
  const int* begin = base_inner_.data() + base_outer_[col];
  const int* end = base_inner_.data() + base_outer_[col + 1];
  const int* at = std::lower_bound(begin, end, row);
  return at != end && *at == row ? static_cast<int>(at - base_inner_.data()) : -1;
}

void SparseHessian::rebuild_pattern() {
  pattern_version_ = next_pattern_version++;
  extra_pairs_.clear();
  for (const auto& [key, block] : extra_) extra_pairs_.push_back(key);
  // Extra row vertices per column vertex; extra_pairs_ is sorted by row, so sort by column.
  std::vector<std::pair<int, int>> by_column;  // (column vertex, index in extra_pairs_)
  for (std::size_t i = 0; i < extra_pairs_.size(); ++i)
    by_column.emplace_back(extra_pairs_[i].second, static_cast<int>(i));
  std::sort(by_column.begin(), by_column.end(), [&](const auto& x, const auto& y) {
    return x.first != y.first ? x.first < y.first
                              : extra_pairs_[x.second].first < extra_pairs_[y.second].first;
  });
  // Merge each column's base rows with its extra blocks' rows: no extra block lies in the base.
  const int n = rows();
  const int base_nnz = static_cast<int>(base_inner_.size());
  const int nnz = base_nnz + 9 * static_cast<int>(extra_pairs_.size());
  std::vector<int> outer(n + 1, 0), inner;
  inner.reserve(nnz);
  extra_position_.assign(3 * extra_pairs_.size(), 0);
  std::size_t next = 0;  // into by_column
  for (int c = 0; c < num_vertices_; ++c) {
    const std::size_t first = next;
    while (next < by_column.size() && by_column[next].first == c) ++next;
    for (int j = 0; j < 3; ++j) {
      const int col = 3 * c + j;
      int k = base_outer_[col];
      std::size_t x = first;
      while (k < base_outer_[col + 1] || x < next) {
        const int extra_row = x < next ? 3 * extra_pairs_[by_column[x].second].first : n;
        if (k < base_outer_[col + 1] && base_inner_[k] < extra_row) {
          base_position_[k] = static_cast<int>(inner.size());
          inner.push_back(base_inner_[k++]);
        } else {
          extra_position_[3 * by_column[x].second + j] = static_cast<int>(inner.size());
          for (int i = 0; i < 3; ++i) inner.push_back(extra_row + i);
          ++x;
        }
      }
      outer[col + 1] = static_cast<int>(inner.size());
    }
  }
  std::vector<double> zeros(nnz, 0.0);
  matrix_ = Eigen::Map<const Eigen::SparseMatrix<double>>(n, n, nnz, outer.data(), inner.data(),
                                                          zeros.data());
  matrix_.makeCompressed();
}

void SparseHessian::set_zero() {
  in_order_next_ = -1;
  ++generation_;  // the element blocks: cleared as they are handed out or in assemble()
  for (int v : touched_vertices_) {
    vertex_values_[v].setZero();
    vertex_touched_[v] = 0;
  }
  touched_vertices_.clear();
  direct_used_ = false;  // direct_ is stale now: zeroed or overwritten by its next writer
  extra_.clear();
  projection_active_ = false;
}

Eigen::Matrix3d& SparseHessian::vertex_block(int v) {
  if (!vertex_touched_[v]) {
    vertex_touched_[v] = 1;
    touched_vertices_.push_back(v);
  }
  return vertex_values_[v];
}

void SparseHessian::add_vertex_pair_block(int a, int b, const Eigen::Matrix3d& B) {
  if (a == b) {
    vertex_block(a) += 0.5 * (B + B.transpose());
    return;
  }
  // Stored: the lower triangle, i.e. the block with the larger vertex as row.
  const int r = std::max(a, b), c = std::min(a, b);
  const Eigen::Matrix3d L = a > b ? B : Eigen::Matrix3d(B.transpose());
  const int k0 = base_entry(3 * r, 3 * c);
  if (k0 < 0) {
    auto [at, inserted] = extra_.try_emplace({r, c}, L);
    if (!inserted) at->second += L;
    return;
  }
  use_direct();
  for (int j = 0; j < 3; ++j) {
    const int k = base_entry(3 * r, 3 * c + j);
    for (int i = 0; i < 3; ++i) direct_[k + i] += L(i, j);  // rows 3r, 3r+1, 3r+2 are adjacent
  }
}

void SparseHessian::add_matrix(double scale, const Eigen::SparseMatrix<double>& A) {
  if (A.rows() != rows() || A.cols() != rows() || !A.isCompressed()) {
    throw std::logic_error("SparseHessian: add_matrix needs a compressed " +
                           std::to_string(rows()) + "-square matrix");
  }
  const bool base = A.nonZeros() == static_cast<Eigen::Index>(base_inner_.size()) &&
                    std::equal(base_outer_.begin(), base_outer_.end(), A.outerIndexPtr()) &&
                    std::equal(base_inner_.begin(), base_inner_.end(), A.innerIndexPtr());
  const Eigen::Map<const Eigen::VectorXd> values(A.valuePtr(), A.nonZeros());
  if (base && !direct_used_) {
    direct_.noalias() = scale * values;  // the first term: 0 + x = x, without zeroing first
    direct_used_ = true;
  } else if (base) {
    direct_ += scale * values;
  } else {
    use_direct();
    for (int col = 0; col < A.cols(); ++col) {
      for (Eigen::SparseMatrix<double>::InnerIterator it(A, col); it; ++it) {
        const int row = static_cast<int>(it.row());
        if (row < col) continue;  // the upper triangle is not read
        const int k = base_entry(row, col);
        if (k >= 0) {
          direct_[k] += scale * it.value();
        } else {
          auto [at, inserted] = extra_.try_emplace({row / 3, col / 3}, Eigen::Matrix3d::Zero());
          at->second(row % 3, col % 3) += scale * it.value();
        }
      }
    }
  }
}

bool SparseHessian::begin_elements_in_order() {
  if (in_order_next_ >= 0) return false;
  for (int e = 0; e < num_elements_; ++e) {
    if (element_generation_[e] == generation_) return false;
  }
  if (direct_used_) {
    in_order_sum_ = direct_;
  } else {
    in_order_sum_.setZero(direct_.size());
  }
  direct_used_ = false;  // direct values added from now on are summed after the elements
  in_order_next_ = 0;
  return true;
}

void SparseHessian::add_element_in_order(int e, const double* packed) {
  if (e != in_order_next_ || e >= num_elements_) {
    throw std::logic_error("SparseHessian: element " + std::to_string(e) +
                           " handed out of order (expected " + std::to_string(in_order_next_) + ")");
  }
  const int* target = element_target_.data() + std::size_t(e) * kPacked;
  double* sum = in_order_sum_.data();
  for (int p = 0; p < kPacked; ++p) sum[target[p]] += packed[p];
  ++in_order_next_;
}

void SparseHessian::use_direct() {
  if (direct_used_) return;
  direct_.setZero();
  direct_used_ = true;
}

const Eigen::SparseMatrix<double>& SparseHessian::assemble() {
  bool same = extra_.size() == extra_pairs_.size();
  if (same) {
    std::size_t i = 0;
    for (const auto& [key, block] : extra_) {
      if (key != extra_pairs_[i++]) {
        same = false;
        break;
      }
    }
  }
  if (!same) rebuild_pattern();
  const int nnz = static_cast<int>(base_inner_.size());
  double* values = matrix_.valuePtr();
  const int* position = base_position_.data();
  const bool in_order = in_order_next_ >= 0;
  if (in_order && in_order_next_ != num_elements_) {
    throw std::logic_error("SparseHessian: assemble() after " + std::to_string(in_order_next_) +
                           " of " + std::to_string(num_elements_) + " elements in order");
  }
  bool buffered = !in_order;  // element blocks to gather
  for (int e = 0; e < num_elements_ && !buffered; ++e) buffered = element_generation_[e] == generation_;
  if (buffered) {
    // Blocks nobody touched in this assembly still hold an older one's values.
    for (int e = 0; e < num_elements_; ++e) {
      if (element_generation_[e] != generation_) element_block(e);
    }
  }
  if (!in_order) use_direct();  // zero when no form added to it
  const double* elem = element_values_.data();
  const double* direct = direct_.data();
  const double* first = in_order ? in_order_sum_.data() : direct;
  const bool late_direct = in_order && direct_used_;
#pragma omp parallel for schedule(static) if (nnz > kParallelEntries)
  for (int k = 0; k < nnz; ++k) {
    double sum = first[k];
    if (late_direct) sum += direct[k];
    if (buffered) {
      for (int s = source_start_[k]; s < source_start_[k + 1]; ++s) sum += elem[sources_[s]];
    }
    values[position[k]] = sum;
  }
  std::vector<int> sorted = touched_vertices_;
  std::sort(sorted.begin(), sorted.end());
  for (int v : sorted) {
    const Eigen::Matrix3d& B = vertex_values_[v];
    int p = 0;
    for (int j = 0; j < 3; ++j) {
      for (int i = j; i < 3; ++i) values[position[diagonal_entries_[6 * v + p++]]] += B(i, j);
    }
  }
  // Every extra entry belongs to one block of extra_ (the pattern was just made to match it).
  std::size_t x = 0;
  for (const auto& [key, L] : extra_) {
    for (int j = 0; j < 3; ++j) {
      for (int i = 0; i < 3; ++i) values[extra_position_[3 * x + j] + i] = L(i, j);
    }
    ++x;
  }
  return matrix_;
}

void SparseHessian::eliminate_dofs(const std::vector<char>& fixed) {
  double* values = matrix_.valuePtr();
  const int* outer = matrix_.outerIndexPtr();
  const int* inner = matrix_.innerIndexPtr();
  for (int j = 0; j < matrix_.cols(); ++j) {
    for (int k = outer[j]; k < outer[j + 1]; ++k) {
      const int i = inner[k];
      if (fixed[i] || fixed[j]) values[k] = i == j ? 1.0 : 0.0;
    }
  }
}

Eigen::SparseMatrix<double> SparseHessian::zero_matrix() const {
  Eigen::SparseMatrix<double> Z = matrix_;
  Eigen::Map<Eigen::VectorXd>(Z.valuePtr(), Z.nonZeros()).setZero();
  return Z;
}

}  // namespace rbaa
