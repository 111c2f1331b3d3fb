// `rbaa gradcheck` on a coarse ball scene: prints one line per direction and PASS, exits 0; an
// impossible tolerance makes it print FAIL and exit non-zero.

#include <gtest/gtest.h>

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

TEST(GradcheckVerb, PassesOnTheBallAndFailsOnAnImpossibleTolerance) {
  const VerbRun ok = run_verb("--fields=Y,rho --directions=2");
  std::printf("%s", ok.output.c_str());
  EXPECT_EQ(ok.status, 0);
  EXPECT_NE(ok.output.find("direction  1:"), std::string::npos);
  EXPECT_NE(ok.output.find("PASS"), std::string::npos);

  const VerbRun bad = run_verb("--fields=nu --directions=1 --gradcheck_tolerance=1e-300 --factor_storage=rebuild");
  EXPECT_NE(bad.status, 0);
  EXPECT_NE(bad.output.find("FAIL"), std::string::npos) << bad.output;

  const VerbRun typo = run_verb("--fields=Young");
  EXPECT_NE(typo.status, 0);
  EXPECT_NE(typo.output.find("Young"), std::string::npos) << typo.output;
}

}  // namespace
