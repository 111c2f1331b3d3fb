// The expressions the PolyFEM export writes (io/polyfem_scene.hpp), evaluated by a small parser
// of the tinyexpr subset they use (numbers, x y z t, + - * /, parentheses, cos, sin), against
// the rigid motions they stand for.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cctype>
#include <cmath>
#include <stdexcept>
#include <string>

#include "io/io_test_support.hpp"
#include "rbaa/scene/polyfem_scene.hpp"
#include "rbaa/sim/world.hpp"

namespace {

class Expression {
 public:
  Expression(const std::string& text, double x, double y, double z, double t)
      : s_(text), vars_{x, y, z, t} {}
  double value() {
    const double v = sum();
    if (i_ != s_.size()) throw std::runtime_error("trailing text at " + std::to_string(i_));
    return v;
  }

 private:
  double sum() {
    double v = product();
    while (i_ < s_.size() && (s_[i_] == '+' || s_[i_] == '-')) {
      const char op = s_[i_++];
      const double w = product();
      v = op == '+' ? v + w : v - w;
    }
    return v;
  }
  double product() {
    double v = unary();
    while (i_ < s_.size() && (s_[i_] == '*' || s_[i_] == '/')) {
      const char op = s_[i_++];
      const double w = unary();
      v = op == '*' ? v * w : v / w;
    }
    return v;
  }
  double unary() {
    if (s_[i_] == '-') return ++i_, -unary();
    if (s_[i_] == '(') {
      ++i_;
      const double v = sum();
      if (s_[i_++] != ')') throw std::runtime_error("missing )");
      return v;
    }
    if (std::isdigit(static_cast<unsigned char>(s_[i_]))) {
      std::size_t used = 0;
      const double v = std::stod(s_.substr(i_), &used);
      i_ += used;
      return v;
    }
    for (const char* f : {"cos(", "sin("}) {
      if (s_.compare(i_, 4, f) == 0) {
        i_ += 3;
        const double a = unary();
        return f[0] == 'c' ? std::cos(a) : std::sin(a);
      }
    }
    const std::string names = "xyzt";
    const auto k = names.find(s_[i_]);
    if (k == std::string::npos) throw std::runtime_error("unexpected '" + s_.substr(i_, 1) + "'");
    ++i_;
    return vars_[k];
  }

  std::string s_;
  std::size_t i_ = 0;
  double vars_[4];
};

Eigen::Vector3d evaluate(const std::array<std::string, 3>& e, const Eigen::Vector3d& p, double t) {
  return {Expression(e[0], p.x(), p.y(), p.z(), t).value(),
          Expression(e[1], p.x(), p.y(), p.z(), t).value(),
          Expression(e[2], p.x(), p.y(), p.z(), t).value()};
}

TEST(PolyfemScene, RigidVelocityExpressionsAreTheRigidField) {
  const Eigen::Vector3d c(0.3, -0.2, 1.5), v(-3.5, 3.5, -2.4), w(1.0, -2.0, 0.5);
  const auto e = rbaa::rigid_velocity_expressions(c, v, w);
  for (const Eigen::Vector3d& p : {Eigen::Vector3d(0.4, -0.1, 1.6), Eigen::Vector3d(-1, 2, -3)}) {
    const Eigen::Vector3d expected = v + w.cross(p - c);
    EXPECT_LE((evaluate(e, p, 0.0) - expected).norm(), 1e-14 * (1 + expected.norm()))
        << p.transpose();
  }
}

TEST(PolyfemScene, DriveDisplacementIsThePrescribedMotion) {
  rbaa::PrescribedMotion m;
  m.axis = Eigen::Vector3d(1, 2, 2).normalized();
  m.centre = Eigen::Vector3d(0.11, -0.1, 0.02);
  m.angular_velocity = 3.9269908169872414;
  m.velocity = Eigen::Vector3d(0.5, -1, 0.25);
  const auto e = rbaa::drive_displacement_expressions(m, "test");
  for (double t : {0.0, 0.01, 0.3, 1.7}) {
    for (const Eigen::Vector3d& p :
         {Eigen::Vector3d(0.12, -0.11, 0.0), Eigen::Vector3d(0.5, 0.3, -0.8)}) {
      const Eigen::Vector3d expected = m.position(p, t) - p;
      EXPECT_LE((evaluate(e, p, t) - expected).norm(), 1e-14) << "t " << t;
    }
  }
  m.angular_velocity_table = {Eigen::Vector2d(0, 1), Eigen::Vector2d(1, 2)};
  const std::string msg = rbaa::test::input_error_message(
      [&] { rbaa::drive_displacement_expressions(m, "bodies[0]"); });
  EXPECT_NE(msg.find("bodies[0]: a drive with an angular velocity table is not exported"),
            std::string::npos)
      << msg;
}

}  // namespace
