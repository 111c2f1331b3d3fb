#include <gtest/gtest.h>

#include <limits>
#include <string>

#include "rbaa/error.hpp"
#include "rbaa/material/material_field.hpp"

namespace rbaa {
namespace {

std::string validation_message(const MaterialField& f) {
  try {
    validate_material_field(f, f.size(), "m.csv");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// The message states the interval a value must lie in, brackets included: nu = 0.5 makes Lame's
// lambda = Y nu / ((1 + nu)(1 - 2 nu)) infinite, so (-1, 0.5) is open at both ends.
TEST(MaterialField, OutOfRangeMessagesStateTheAdmissibleInterval) {
  const MaterialField ok = MaterialField::uniform(3, 1e10, 0.3, 2500, 1.0);
  EXPECT_EQ(validation_message(ok), "");

  MaterialField f = ok;
  f.nu[1] = 0.5;
  EXPECT_EQ(validation_message(f),
            "m.csv: material field 'nu' of element 1 is 0.5, outside (-1, 0.5)");
  f.nu[1] = -1.0;
  EXPECT_EQ(validation_message(f),
            "m.csv: material field 'nu' of element 1 is -1, outside (-1, 0.5)");
  f.nu[1] = 0.49999999;  // inside: lambda is large but finite
  EXPECT_EQ(validation_message(f), "");

  f = ok;
  f.Y[2] = std::numeric_limits<double>::infinity();
  EXPECT_EQ(validation_message(f),
            "m.csv: material field 'Y' of element 2 is inf, outside (0, inf)");
  f = ok;
  f.rho[0] = 0;
  EXPECT_EQ(validation_message(f),
            "m.csv: material field 'rho' of element 0 is 0, outside (0, inf)");
  f = ok;
  f.alpha[0] = 1.5;
  EXPECT_EQ(validation_message(f),
            "m.csv: material field 'alpha' of element 0 is 1.5, outside (0, 1]");
}

}  // namespace
}  // namespace rbaa
