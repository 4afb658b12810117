// Compiled with -mavx2 -mfma (kernel/CMakeLists.txt); see Tensor_product.h for why it includes
// nothing but intrinsics.
#include <immintrin.h>

#include <cstddef>

#include "kernel/internal/Tensor_product.h"

namespace extremal::internal {

namespace {

// The six homogeneous sums S00, S10, S01, S20, S11, S02 (x, y, z, w in one register each).
struct Sums {
  __m256d s[6];
};

// One 4-wide FMA per pole and derivative order. P, Q > 0 fix the degrees at compile time
// (loops unrolled), 0 reads p, q.
template <int P, int Q, int Order>
inline __attribute__((always_inline)) Sums sum_poles(const double* poles,
                                                     std::ptrdiff_t row_stride, const double* nu,
                                                     const double* nv, int basis_stride,
                                                     int basis_step, int p, int q) {
  if constexpr (P > 0) p = P;
  if constexpr (Q > 0) q = Q;
  const __m256d zero = _mm256_setzero_pd();
  Sums r;
  for (__m256d& x : r.s) x = zero;
  for (int i = 0; i <= p; ++i) {
    const double* row = poles + 4 * i * row_stride;
    __m256d t0 = zero, t1 = zero, t2 = zero;
    for (int j = 0; j <= q; ++j) {
      const __m256d pole = _mm256_loadu_pd(row + 4 * j);
      const double* nvj = nv + j * basis_step;
      t0 = _mm256_fmadd_pd(_mm256_broadcast_sd(nvj), pole, t0);
      if constexpr (Order >= 1)
        t1 = _mm256_fmadd_pd(_mm256_broadcast_sd(nvj + basis_stride), pole, t1);
      if constexpr (Order >= 2)
        t2 = _mm256_fmadd_pd(_mm256_broadcast_sd(nvj + 2 * basis_stride), pole, t2);
    }
    const double* nui = nu + i * basis_step;
    const __m256d n0 = _mm256_broadcast_sd(nui);
    r.s[0] = _mm256_fmadd_pd(n0, t0, r.s[0]);
    if constexpr (Order >= 1) {
      const __m256d n1 = _mm256_broadcast_sd(nui + basis_stride);
      r.s[1] = _mm256_fmadd_pd(n1, t0, r.s[1]);
      r.s[2] = _mm256_fmadd_pd(n0, t1, r.s[2]);
      if constexpr (Order >= 2) {
        const __m256d n2 = _mm256_broadcast_sd(nui + 2 * basis_stride);
        r.s[3] = _mm256_fmadd_pd(n2, t0, r.s[3]);
        r.s[4] = _mm256_fmadd_pd(n1, t1, r.s[4]);
        r.s[5] = _mm256_fmadd_pd(n0, t2, r.s[5]);
      }
    }
  }
  return r;
}

constexpr int derivative_count(int order) { return order == 0 ? 1 : order == 1 ? 3 : 6; }

template <int P, int Q, int Order>
void tensor_product(const double* poles, std::ptrdiff_t row_stride, const double* nu,
                    const double* nv, int basis_stride, int basis_step, int p, int q, double* s) {
  const Sums r = sum_poles<P, Q, Order>(poles, row_stride, nu, nv, basis_stride, basis_step, p,
                                        q);
  for (int k = 0; k < derivative_count(Order); ++k) _mm256_storeu_pd(s + 4 * k, r.s[k]);
}

// Lane 3 (w) of x in every lane.
inline __m256d broadcast_w(__m256d x) { return _mm256_permute4x64_pd(x, 0xFF); }

// R x for the x, y, z lanes of x (lane 3 of the result is 0 when the columns' lane 3 is).
inline __m256d rotate(const __m256d col[3], __m256d x) {
  __m256d r = _mm256_mul_pd(col[0], _mm256_permute4x64_pd(x, 0x00));
  r = _mm256_fmadd_pd(col[1], _mm256_permute4x64_pd(x, 0x55), r);
  return _mm256_fmadd_pd(col[2], _mm256_permute4x64_pd(x, 0xAA), r);
}

template <int P, int Q, int Order>
void placed_tensor_product(const double* poles, std::ptrdiff_t row_stride, const double* nu,
                           const double* nv, int basis_stride, int basis_step, int p, int q,
                           bool rational, const double* R, const double* t, double* out) {
  Sums r = sum_poles<P, Q, Order>(poles, row_stride, nu, nv, basis_stride, basis_step, p, q);
  __m256d* s = r.s;
  if (rational) {  // quotient rule on A / w, A the Cartesian part
    const __m256d inv = _mm256_div_pd(_mm256_set1_pd(1.0), broadcast_w(s[0]));
    s[0] = _mm256_mul_pd(s[0], inv);
    if constexpr (Order >= 1) {
      const __m256d wu = broadcast_w(s[1]), wv = broadcast_w(s[2]);
      s[1] = _mm256_mul_pd(_mm256_fnmadd_pd(wu, s[0], s[1]), inv);
      s[2] = _mm256_mul_pd(_mm256_fnmadd_pd(wv, s[0], s[2]), inv);
      if constexpr (Order >= 2) {
        const __m256d two = _mm256_set1_pd(2.0);
        __m256d duu = _mm256_fnmadd_pd(_mm256_mul_pd(two, wu), s[1], s[3]);
        s[3] = _mm256_mul_pd(_mm256_fnmadd_pd(broadcast_w(s[3]), s[0], duu), inv);
        __m256d duv = _mm256_fnmadd_pd(wu, s[2], s[4]);
        duv = _mm256_fnmadd_pd(wv, s[1], duv);
        s[4] = _mm256_mul_pd(_mm256_fnmadd_pd(broadcast_w(s[4]), s[0], duv), inv);
        __m256d dvv = _mm256_fnmadd_pd(_mm256_mul_pd(two, wv), s[2], s[5]);
        s[5] = _mm256_mul_pd(_mm256_fnmadd_pd(broadcast_w(s[5]), s[0], dvv), inv);
      }
    }
  }
  const __m256d col[3] = {_mm256_set_pd(0.0, R[2], R[1], R[0]),
                          _mm256_set_pd(0.0, R[5], R[4], R[3]),
                          _mm256_set_pd(0.0, R[8], R[7], R[6])};
  const __m256d translation = _mm256_set_pd(0.0, t[2], t[1], t[0]);
  _mm256_storeu_pd(out, _mm256_add_pd(rotate(col, s[0]), translation));
  for (int k = 1; k < derivative_count(Order); ++k)
    _mm256_storeu_pd(out + 4 * k, rotate(col, s[k]));
}

// Compile-time degrees for the common low-degree patches (planes, conics, bicubics).
#define EXTREMAL_DEGREE_CASES(CALL) \
  if (p == 3 && q == 3) return CALL(3, 3); \
  if (p == 2 && q == 2) return CALL(2, 2); \
  if (p == 2 && q == 1) return CALL(2, 1); \
  if (p == 1 && q == 2) return CALL(1, 2); \
  if (p == 1 && q == 1) return CALL(1, 1); \
  return CALL(0, 0)

template <int Order>
void sum_for_degrees(const double* poles, std::ptrdiff_t row_stride, const double* nu,
                     const double* nv, int basis_stride, int basis_step, int p, int q,
                     double* s) {
#define EXTREMAL_SUM(PP, QQ) \
  tensor_product<PP, QQ, Order>(poles, row_stride, nu, nv, basis_stride, basis_step, p, q, s)
  EXTREMAL_DEGREE_CASES(EXTREMAL_SUM);
#undef EXTREMAL_SUM
}

template <int Order>
void placed_for_degrees(const double* poles, std::ptrdiff_t row_stride, const double* nu,
                        const double* nv, int basis_stride, int basis_step, int p, int q,
                        bool rational, const double* R, const double* t, double* out) {
#define EXTREMAL_PLACED(PP, QQ)                                                              \
  placed_tensor_product<PP, QQ, Order>(poles, row_stride, nu, nv, basis_stride, basis_step, p, \
                                       q, rational, R, t, out)
  EXTREMAL_DEGREE_CASES(EXTREMAL_PLACED);
#undef EXTREMAL_PLACED
}
#undef EXTREMAL_DEGREE_CASES

void tensor_product_avx2(const double* poles, std::ptrdiff_t row_stride, const double* nu,
                         const double* nv, int basis_stride, int basis_step, int p, int q,
                         int order, double* s) {
  switch (order) {
    case 0:
      return sum_for_degrees<0>(poles, row_stride, nu, nv, basis_stride, basis_step, p, q, s);
    case 1:
      return sum_for_degrees<1>(poles, row_stride, nu, nv, basis_stride, basis_step, p, q, s);
    default:
      return sum_for_degrees<2>(poles, row_stride, nu, nv, basis_stride, basis_step, p, q, s);
  }
}

void placed_tensor_product_avx2(const double* poles, std::ptrdiff_t row_stride, const double* nu,
                                const double* nv, int basis_stride, int basis_step, int p, int q,
                                int order, bool rational, const double* R, const double* t,
                                double* out) {
  switch (order) {
    case 0:
      return placed_for_degrees<0>(poles, row_stride, nu, nv, basis_stride, basis_step, p, q,
                                   rational, R, t, out);
    case 1:
      return placed_for_degrees<1>(poles, row_stride, nu, nv, basis_stride, basis_step, p, q,
                                   rational, R, t, out);
    default:
      return placed_for_degrees<2>(poles, row_stride, nu, nv, basis_stride, basis_step, p, q,
                                   rational, R, t, out);
  }
}

}  // namespace

// Defined here so that the CPU check and the kernels agree.
Simd_kernels avx2_kernels() {
  __builtin_cpu_init();
  if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma"))
    return {&tensor_product_avx2, &placed_tensor_product_avx2};
  return {nullptr, nullptr};
}

}  // namespace extremal::internal
