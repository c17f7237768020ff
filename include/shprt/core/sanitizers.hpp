// Which sanitizer this translation unit is built with, for gcc (__SANITIZE_*__) and clang
// (__has_feature; clang 14 does not define gcc's macros). For what must differ under one: an
// address-space limit, which the sanitizers' shadow memory cannot live with
// (scene/isolated_import), and the tests of it.
#pragma once

#if defined(__SANITIZE_ADDRESS__)
#define SHPRT_UNDER_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define SHPRT_UNDER_ASAN 1
#endif
#endif
#ifndef SHPRT_UNDER_ASAN
#define SHPRT_UNDER_ASAN 0
#endif

#if defined(__SANITIZE_THREAD__)
#define SHPRT_UNDER_TSAN_BUILD 1
#elif defined(__has_feature)
#if __has_feature(thread_sanitizer)
#define SHPRT_UNDER_TSAN_BUILD 1
#endif
#endif
#ifndef SHPRT_UNDER_TSAN_BUILD
#define SHPRT_UNDER_TSAN_BUILD 0
#endif

namespace shprt {

inline constexpr bool kAddressSanitizer = SHPRT_UNDER_ASAN != 0;
// Any sanitizer that reserves shadow memory (ASan, TSan).
inline constexpr bool kShadowMemorySanitizer = kAddressSanitizer || SHPRT_UNDER_TSAN_BUILD != 0;

}  // namespace shprt
