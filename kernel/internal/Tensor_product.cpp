#include "kernel/internal/Tensor_product.h"

#include <cstdlib>
#include <cstring>

namespace extremal::internal {

#if !defined(EXTREMAL_HAVE_AVX2_KERNEL)
Simd_kernels avx2_kernels() { return {}; }
#endif

namespace {

Simd_kernels default_kernels() {
  const char* choice = std::getenv("EXTREMAL_SIMD");
  if (choice != nullptr && std::strcmp(choice, "sse2") == 0) return {};
  return avx2_kernels();
}

}  // namespace

Simd_kernels selected_kernels = default_kernels();

void set_fast_tensor_product(bool enabled) {
  selected_kernels = enabled ? default_kernels() : Simd_kernels{};
}

}  // namespace extremal::internal
