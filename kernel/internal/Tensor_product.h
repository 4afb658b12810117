// The tensor-product sum at the heart of NURBS surface evaluation, with a version for CPUs
// with AVX2 and FMA chosen at run time, so the portable build (SSE2 only) still uses them.
//
// The AVX2 version lives in its own translation unit compiled with -mavx2 -mfma. It includes
// no Eigen or other shared inline code (only intrinsics and this header's declarations), so no
// function compiled for AVX2 can be picked by the linker for callers on a CPU without it; its
// interface is plain doubles.
#pragma once

#include <cstddef>

namespace extremal::internal {

// Sums S_kl = sum_i sum_j Nu[k][i] Nv[l][j] P(i, j) for k + l <= order (order 0 to 2) over the
// (p + 1) x (q + 1) homogeneous poles P(i, j) = poles + 4 * (i * row_stride + j) (x, y, z, w),
// with nu[k * basis_stride + i * basis_step] and nv[l * basis_stride + j * basis_step] the
// basis derivatives (basis_step 2: the u and v bases interleaved, as the SSE2 pair computes
// them). Writes s[6][4] in the order S00, S10, S01, S20, S11, S02 (entries above `order`
// untouched).
using Tensor_product_fn = void (*)(const double* poles, std::ptrdiff_t row_stride,
                                   const double* nu, const double* nv, int basis_stride,
                                   int basis_step, int p, int q, int order, double* s);

// The same sum followed by the quotient rule (when `rational`) and a rigid placement: writes
// the point and its derivatives x = R x_body + t (derivatives rotated only) to out[6][4] in
// the order p, du, dv, duu, duv, dvv, entry [k][3] unspecified. R is column-major.
using Placed_tensor_product_fn = void (*)(const double* poles, std::ptrdiff_t row_stride,
                                          const double* nu, const double* nv, int basis_stride,
                                          int basis_step, int p, int q, int order, bool rational,
                                          const double* rotation, const double* translation,
                                          double* out);

// A plain aggregate (no member initialisers: no constructor to compile in the AVX2 unit);
// Simd_kernels{} holds two nullptrs.
struct Simd_kernels {
  Tensor_product_fn sum;
  Placed_tensor_product_fn placed;
};

// The AVX2 + FMA kernels if this build has them and this CPU runs them, else nullptr.
Simd_kernels avx2_kernels();

// The kernels Nurbs_surface_3::evaluate uses: the AVX2 ones when available, unless the
// environment variable EXTREMAL_SIMD is "sse2" (to test or compare the portable path), else
// nullptr (the portable code inside evaluate). set_fast_tensor_product(false) switches them off
// for tests (not thread-safe: call it while no evaluation runs).
// Chosen when the library loads (evaluations during static initialisation elsewhere may still
// see nullptr and take the portable path, which gives the same values up to rounding).
extern Simd_kernels selected_kernels;
inline const Simd_kernels& fast_kernels() { return selected_kernels; }
void set_fast_tensor_product(bool enabled);

}  // namespace extremal::internal
