// Flags that several verbs read, defined once (gflags allows one definition per name).

#include <gflags/gflags.h>

DEFINE_string(out, "", "output: the tet mesh file for `mesh` (.msh Gmsh 4.1, .mesh MEDIT, .node/.ele TetGen); "
                       "the output folder for `simulate`, `attack`, `evaluate`, `study` and `sweep`");
DEFINE_string(materials, "", "per-element materials: CSV with Y,nu,rho,alpha columns (one row per tet) or an "
                             "rbaa .msh with element data of those names");
DEFINE_string(factor_storage, "store", "backward pass: 'store' keeps each step's Cholesky factor from the forward "
                                       "run (fast; memory ~ steps x one factor), 'rebuild' refactorises in the "
                                       "backward pass (less memory)");
