// The rest of the no-heap check of tests/cpp/support/no_heap.hpp: the failure report, and the
// allocations that Eigen does not see (std containers, new, malloc under AddressSanitizer) failing
// inside a no-heap scope too. Linked into every test executable (an object library, so that the
// replaced operator new is always the one linked).
#include <Eigen/Core>
#include <cstdio>
#include <cstdlib>
#include <new>

#if defined(__SANITIZE_ADDRESS__)
#define QUATNAV_TEST_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define QUATNAV_TEST_ASAN 1
#endif
#endif

#ifdef QUATNAV_TEST_ASAN
#include <sanitizer/allocator_interface.h>
#include <sanitizer/common_interface_defs.h>
#elif defined(__GLIBC__)
#include <execinfo.h>
#include <unistd.h>
#endif

namespace quatnav_test {

void heap_in_no_heap_scope(const char* what, const char* file, int line) noexcept {
  // Allow the heap again: printing the report may allocate.
  Eigen::internal::set_is_malloc_allowed(true);
  std::fprintf(stderr,
               "\nquatnav tests: %s inside a no-heap scope (Eigen::internal::set_is_malloc_allowed(false)), "
               "detected at %s:%d; the stack:\n",
               what, file, line);
  std::fflush(stderr);
#ifdef QUATNAV_TEST_ASAN
  __sanitizer_print_stack_trace();
#elif defined(__GLIBC__)
  void* frames[64];
  backtrace_symbols_fd(frames, backtrace(frames, 64), STDERR_FILENO);
#endif
  std::abort();
}

}  // namespace quatnav_test

#ifdef QUATNAV_TEST_ASAN
// AddressSanitizer keeps its own operator new (its new/delete mismatch checks); it calls this hook,
// a weak function of its runtime, for every malloc and new of the program. (Its
// __sanitizer_install_malloc_and_free_hooks installs nothing in LLVM 14's runtime.)
extern "C" void __sanitizer_malloc_hook(const volatile void*, std::size_t) {
  if (!Eigen::internal::is_malloc_allowed())
    quatnav_test::heap_in_no_heap_scope("a heap allocation", __FILE__, __LINE__);
}
#else
// The replaceable allocation functions that the others (new[], nothrow) call in libstdc++ and
// libc++; the default operator delete frees what malloc and aligned_alloc return.
void* operator new(std::size_t size) {
  if (!Eigen::internal::is_malloc_allowed()) quatnav_test::heap_in_no_heap_scope("operator new", __FILE__, __LINE__);
  if (size == 0) size = 1;
  for (;;) {
    if (void* p = std::malloc(size)) return p;
    std::new_handler handler = std::get_new_handler();
    if (handler == nullptr) throw std::bad_alloc();
    handler();
  }
}

void* operator new(std::size_t size, std::align_val_t alignment) {
  if (!Eigen::internal::is_malloc_allowed())
    quatnav_test::heap_in_no_heap_scope("operator new (aligned)", __FILE__, __LINE__);
  const std::size_t align = static_cast<std::size_t>(alignment);
  if (size == 0) size = 1;
  size = (size + align - 1) / align * align;  // aligned_alloc wants a multiple of the alignment
  for (;;) {
    if (void* p = std::aligned_alloc(align, size)) return p;
    std::new_handler handler = std::get_new_handler();
    if (handler == nullptr) throw std::bad_alloc();
    handler();
  }
}
#endif
