// tiltfield (internal): TF_VECTOR_CLONES before a function builds it for AVX-512, AVX2 and baseline x86-64,
// and the best is picked at load time (GCC target clones). For loops the compiler vectorises only with
// the wider instruction sets (baseline SSE2 has no cheap way from a double compare to a byte mask, for
// one). Off under the sanitizers, whose runtime does not take target clones, and on other compilers.
// Not part of the API.
#pragma once

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(__SANITIZE_ADDRESS__)
#define TF_VECTOR_CLONES __attribute__((target_clones("avx512f", "avx2", "default")))
#else
#define TF_VECTOR_CLONES
#endif
