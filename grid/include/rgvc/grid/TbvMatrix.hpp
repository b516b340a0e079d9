// T, the temporal-bounding-volume matrix (seed 004 §3, §4.1, §5.2): TbvRegion.hpp (the regions, their
// discretization and why the boundary suffices), TbvMatrix2D.hpp and TbvMatrix3D.hpp (the stores).
#pragma once

#include "rgvc/grid/TbvMatrix2D.hpp"
#include "rgvc/grid/TbvMatrix3D.hpp"
