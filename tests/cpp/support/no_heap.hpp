// "No heap in any step" as a check in every build of the C++ tests, Release included.
//
// tests/cpp/CMakeLists.txt force-includes this header first into every unit of every test
// executable (-include), so that each unit sees the same definitions (one rule for the whole
// program: Eigen's inline allocation functions must not differ between units).
//
// A test marks a no-heap scope with Eigen's own switch:
//     Eigen::internal::set_is_malloc_allowed(false);  ...steps...  set_is_malloc_allowed(true);
// Eigen checks that switch in every allocation it makes (check_that_malloc_is_allowed) with
// eigen_assert, which NDEBUG turns into nothing: in a Release build the check was inert. The
// eigen_assert below keeps every other Eigen assertion exactly as Eigen defines it (eigen_plain_assert:
// on without NDEBUG, off with it) and makes only the heap assertion, recognised at compile time by
// its text, abort in every build. tests/cpp/support/no_heap.cpp adds the allocations Eigen does not
// see (std containers, new): operator new fails inside a scope too (under AddressSanitizer, whose
// own operator new stays, its allocation hook does the same). tests/cpp/test_no_heap_check.cpp
// shows in each build that both fire.
#pragma once

#ifndef EIGEN_RUNTIME_NO_MALLOC
#define EIGEN_RUNTIME_NO_MALLOC
#endif

namespace quatnav_test {

// Whether `text` contains `part` (a constant expression: decides at compile time which assertion
// an eigen_assert is).
constexpr bool text_contains(const char* text, const char* part) {
  for (; *text != '\0'; ++text) {
    const char* a = text;
    const char* b = part;
    while (*b != '\0' && *a == *b) {
      ++a;
      ++b;
    }
    if (*b == '\0') return true;
  }
  return false;
}

// Prints where the heap was used inside a no-heap scope (with a stack trace) and aborts.
[[noreturn]] void heap_in_no_heap_scope(const char* what, const char* file, int line) noexcept;

}  // namespace quatnav_test

// The text of Eigen 3.4's check (Eigen/src/Core/util/Memory.h, check_that_malloc_is_allowed).
#define QUATNAV_TEST_EIGEN_HEAP_ASSERTION "heap allocation is forbidden"

#define eigen_assert(x)                                                                             \
  do {                                                                                              \
    if constexpr (::quatnav_test::text_contains(#x, QUATNAV_TEST_EIGEN_HEAP_ASSERTION)) {          \
      if (!(x)) ::quatnav_test::heap_in_no_heap_scope("an Eigen allocation", __FILE__, __LINE__); \
    } else {                                                                                        \
      eigen_plain_assert(x);                                                                        \
    }                                                                                               \
  } while (false)
