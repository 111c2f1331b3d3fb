// `rbaa gradcheck` on a coarse ball scene: prints one line per direction and PASS, exits 0; an
// impossible tolerance makes it print FAIL and exit non-zero.

#include <gtest/gtest.h>

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <string>

namespace {

struct VerbRun {
  int status = -1;
  std::string output;
};

VerbRun run_verb(const std::string& args) {
  const std::string cmd = std::string(RBAA_EXECUTABLE) + " gradcheck --config=" RBAA_SOURCE_DIR
                          "/configs/ball.yaml --set='mesh.target_tets=300' " + args + " 2>&1";
  VerbRun r;
  FILE* pipe = popen(cmd.c_str(), "r");
  if (pipe == nullptr) return r;
  std::array<char, 4096> buf;
  while (fgets(buf.data(), buf.size(), pipe) != nullptr) r.output += buf.data();
  r.status = pclose(pipe);
  return r;
}

// The tangent method on the stiff star (where Y's finite differences drown in Newton's noise):
// the tangent line says PASS at 1e-10; an impossible tolerance is a FAIL with exit 1.
TEST(GradcheckVerb, TangentMethodOnTheStar) {
  const std::string star = " --config=" RBAA_SOURCE_DIR "/configs/star.yaml ";
  const VerbRun ok = run_verb(star + "--method=both --fields=Y --directions=2");
  std::printf("%s", ok.output.c_str());
  EXPECT_NE(ok.output.find("tangent"), std::string::npos);
  EXPECT_NE(ok.output.find("PASS: max relative error"), std::string::npos) << ok.output;
  EXPECT_NE(ok.output.find("tangent; "), std::string::npos) << ok.output;
  // Y's finite differences agree here since the elastic gradient lost its rigid round-off
  // (elastic_form.cpp); nu's, which move the objective 20x less, differ from the adjoint by Newton's
  // noise at the default tolerance, which depends on the machine's rounding (measured 4.6e-6 and
  // 4.5e-7 on two AMD EPYC machines): a finite-difference bar of 1e-9, below what central
  // differences at step 0.01 resolve anywhere, fails that direction, and its line says how the
  // estimates at the step and at 4x the step compare.
  const VerbRun nu = run_verb(star + "--method=fd --fields=nu --directions=1 --gradcheck_tolerance=1e-9");
  EXPECT_NE(nu.output.find("at 4x the step"), std::string::npos) << nu.output;

  const VerbRun bad = run_verb(star + "--method=tangent --fields=Y --directions=1 --tangent_tolerance=1e-300 "
                                      "--tangent_noise_factor=0");
  EXPECT_EQ(WEXITSTATUS(bad.status), 1) << bad.output;
  EXPECT_NE(bad.output.find("FAIL: max relative error"), std::string::npos) << bad.output;

  const VerbRun typo = run_verb(star + "--method=adjoint");
  EXPECT_NE(typo.status, 0);
  EXPECT_NE(typo.output.find("'adjoint'"), std::string::npos) << typo.output;
}

// Issue 14's opening case: the stiff star's Y and nu, whose finite differences were lost in
// Newton's noise (max relative error 1.6e-4 and 5.8e-3 at the default tolerance) while a tighter
// tolerance stalled. At newton.tolerance 1e-12 every step now converges (no round-off floor) and
// finite differences agree with the adjoint within the FD bar, field by field.
TEST(GradcheckVerb, FiniteDifferencesOfTheStarsYAndNuPassAtATightTolerance) {
  const std::string star = " --config=" RBAA_SOURCE_DIR "/configs/star.yaml --set=newton.tolerance=1e-12 ";
  for (const char* field : {"Y", "nu"}) {
    const VerbRun r = run_verb(star + "--method=fd --directions=2 --fields=" + field);
    std::printf("%s", r.output.c_str());
    EXPECT_EQ(WEXITSTATUS(r.status), 0) << field << "\n" << r.output;
    EXPECT_NE(r.output.find("PASS: max relative error"), std::string::npos) << field << "\n" << r.output;
    EXPECT_EQ(r.output.find("round-off floor"), std::string::npos) << field << "\n" << r.output;
  }
}

TEST(GradcheckVerb, PassesOnTheBallAndFailsOnAnImpossibleTolerance) {
  const VerbRun ok = run_verb("--fields=Y,rho --directions=2");
  std::printf("%s", ok.output.c_str());
  EXPECT_EQ(ok.status, 0);
  EXPECT_NE(ok.output.find("direction  1:"), std::string::npos);
  EXPECT_NE(ok.output.find("PASS"), std::string::npos);
  // The check covered contact: "contact in K of N steps" with K > 0, and no "no contact" note.
  const std::size_t at = ok.output.find("contact in ");
  ASSERT_NE(at, std::string::npos) << ok.output;
  EXPECT_GT(std::stoi(ok.output.substr(at + 11)), 0) << ok.output;
  EXPECT_EQ(ok.output.find("no contact"), std::string::npos) << ok.output;

  // Material-space directions: a non-zero gradient norm is printed and the check passes.
  const VerbRun material = run_verb("--fields=rho --directions=1 --fd_space=material");
  EXPECT_EQ(material.status, 0) << material.output;
  const std::size_t g_at = material.output.find("|gradient| ");
  ASSERT_NE(g_at, std::string::npos) << material.output;
  EXPECT_GT(std::stod(material.output.substr(g_at + 11)), 0.0) << material.output;

  // Below any achievable tolerance finite differences are either wrong or noise: never PASS.
  const VerbRun bad = run_verb("--fields=nu --directions=1 --gradcheck_tolerance=1e-300 --factor_storage=rebuild");
  EXPECT_NE(bad.status, 0);
  EXPECT_TRUE(bad.output.find("FAIL") != std::string::npos ||
              bad.output.find("INCONCLUSIVE") != std::string::npos)
      << bad.output;
  EXPECT_EQ(bad.output.find("PASS"), std::string::npos) << bad.output;

  const VerbRun typo = run_verb("--fields=Young");
  EXPECT_NE(typo.status, 0);
  EXPECT_NE(typo.output.find("Young"), std::string::npos) << typo.output;
}

}  // namespace

// Issue 16: the directed objective (the struck ball's final x) through body-body contact into the
// driven bat's materials, on a coarse bat and ball (as tests/opt/test_attack_bat.cpp), per field
// against the tangent-linear model (the bat is stiff: Y and nu's finite differences drown in
// Newton's noise there; the soft miniature bat of test_driven_gradient.cpp checks both methods).
// Measured 2026-11-26: max relative errors 8.3e-13 (Y), 2.0e-12 (nu), 1.2e-12 (rho), 9.7e-13
// (alpha), ~1.3 s per tangent.
TEST(GradcheckVerb, TheBatsDirectedObjectiveMatchesTheTangentPerField) {
  const std::string bat =
      " --config=" RBAA_SOURCE_DIR "/configs/bat.yaml --set=mesh.target_tets=600 "
      "--set=object.driven.vertices.depth=0.02 '--set=bodies=[{name: ball, mesh: {shape: sphere, "
      "radius: 0.0366, target_tets: 200}, position: [0.75, 1.25, 0.245], velocity: [0, -6, 0]}]' "
      "--set=time.step=0.002 --method=tangent --directions=2 ";
  for (const char* field : {"Y", "nu", "rho", "alpha"}) {
    const VerbRun r = run_verb(bat + "--fields=" + field);
    std::printf("%s:\n%s", field, r.output.c_str());
    EXPECT_EQ(r.status, 0) << field << "\n" << r.output;
    EXPECT_NE(r.output.find("objective target on body 'ball'"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("PASS: max relative error"), std::string::npos) << field << "\n" << r.output;
    // The ball touched the bat: the gradient flowed through body-body contact.
    EXPECT_EQ(r.output.find("contact in 0 of"), std::string::npos) << r.output;
  }
}
