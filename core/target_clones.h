// EPI_TARGET_CLONES: a plain loop the compiler vectorizes, compiled for AVX-512, AVX2 and the
// baseline and chosen at load time (GCC's target_clones). The build has no -march, so a loop
// vectorized without it uses SSE2 only. Without FMA contraction (-ffp-contract=off, or ISO C++
// mode) every clone computes the baseline's bits.
#pragma once

// ThreadSanitizer instruments the ifunc resolver that target_clones generates, and the resolver
// runs before TSan is initialised (a crash at load): the TSan build keeps the default target only.
#if defined(__SANITIZE_THREAD__)
#define EPI_TARGET_CLONES
#elif defined(__has_feature)
#if __has_feature(thread_sanitizer)
#define EPI_TARGET_CLONES
#endif
#endif
#ifndef EPI_TARGET_CLONES
#define EPI_TARGET_CLONES __attribute__((target_clones("avx512f", "avx2", "default")))
#endif
