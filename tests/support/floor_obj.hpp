#pragma once
// A square floor for scenes with an obstacle mesh: two triangles in the plane z = 0 with corners
// (+-h, +-h, 0), wound so that their normal is +z, as the text of an OBJ file.

#include <sstream>
#include <string>

namespace rbaa::test {

/// The OBJ text of the floor of half-width `h` m (the square's side is 2 h).
inline std::string floor_obj(double h) {
  std::ostringstream obj;
  obj << "v " << -h << " " << -h << " 0\nv " << h << " " << -h << " 0\nv " << h << " " << h
      << " 0\nv " << -h << " " << h << " 0\nf 1 2 3\nf 1 3 4\n";
  return obj.str();
}

}  // namespace rbaa::test
