#pragma once
// Internal to core: the per-point loops that dominate the robust and tracked methods are
// compiled three times, for AVX-512, AVX2 and the x86-64 baseline, and the loader picks the one
// the CPU runs (GCC's target_clones). Results are the same bit for bit on all three: reductions
// run in a fixed number of lanes (kLanes) whatever the vector width, and no multiply-add is
// contracted into a fused one (-ffp-contract=off for every project target).
//
// Not in sanitized or fuzzing builds (their runtime and the clones' resolvers are not meant to
// meet) nor with compilers other than GCC on x86-64: there the plain loop is compiled once.

#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && !defined(__SANITIZE_ADDRESS__) && \
    !defined(FMCW_NO_VECTOR_CLONES)
#define FMCW_VECTOR_CLONES __attribute__((target_clones("avx512f", "avx2", "default")))
#else
#define FMCW_VECTOR_CLONES
#endif

namespace fmcw::core {

/// Lanes of the fixed-order reductions: point k goes to lane k % kLanes, the lanes are summed
/// in order at the end. Eight doubles fill one AVX-512 register.
constexpr int kLanes = 8;

}  // namespace fmcw::core
