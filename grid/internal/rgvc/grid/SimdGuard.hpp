// The start-up check of an RGVC_SIMD=AVX2 build (grid/src/SimdGuard.cpp). Internal: the libraries'
// translation units that take the object file into every link reference kSimdGuardAnchor.
#pragma once

namespace rgvc::detail {

/// Defined in SimdGuard.cpp, next to the constructor that aborts on a CPU without AVX2 when rgvc was
/// compiled for it. A static library contributes an object file only when a symbol of it is needed, so
/// Culler.cpp keeps a pointer to this one: whatever links the culler links the check.
extern const int kSimdGuardAnchor;

} // namespace rgvc::detail
