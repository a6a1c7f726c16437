// lockstep core: memory for large buffers (frames, depth planes, volumes,
// meshes, the marching-cubes and volume-rendering intermediates), on
// transparent huge pages where the kernel allows it (issue #35).
//
// Why: a buffer's first touch costs a minor page fault per 4 KiB page, about
// 2-8 us each on the 2-core VM lockstep is measured on. A one-shot 256^3
// marching-cubes call touched 72,000 fresh pages (0.57 s of system time,
// three quarters of the call); a 2 MiB huge page takes one fault where 512
// small pages take 512.
//
// How: a buffer of kHugeBytes (1 MiB) and up is placed inside a larger block
// from the ordinary heap (operator new, so a freed block is the next one's
// memory, warm, as core/process_memory.h arranges), on a 2 MiB boundary plus
// a few pages, and the 2 MiB-aligned range it lies on is advised
// MADV_HUGEPAGE before anything is written there. The few pages (0-7, chosen
// by the address) keep buffers allocated one after another from starting at
// the same offset in their huge pages, which slows streaming two of them at
// once (see NoInitAllocator in core/image.h). Smaller blocks are plain
// operator new. A buffer costs up to 2 MiB more memory than its size (its
// last huge page), and 4 MiB more address space.
// Measured (BENCHMARKS.md, "One-shot and warm, huge pages and 4 KiB pages"):
// a one-shot 256^3 gyroid (2.52M triangles) extracts in 0.042 s on two
// threads against 0.18 s on 4 KiB pages (one thread: 0.07-0.2 s against
// 0.25 s, the slow end where the VM's host backs the fresh 2 MiB pages
// first), its whole call takes 0.16-0.23 s against 0.63 s and 1,160 page
// faults against 33,060.
//
// Fallback: where the kernel's mode (/sys/kernel/mm/transparent_hugepage/
// enabled) is `never` or unknown, or LOCKSTEP_HUGE_PAGES=0 is set (tests of
// the fallback; no user needs it), buffers of kSpacedBytes and up start on a
// page and are not advised: the same bytes in the buffer, 4 KiB pages under it.
//
// Inline, header only: the OpenImageIO and peer modules (dlopened, linked to
// nothing of lockstep's) make and free Images too, and every copy of this code
// places and frees a block the same way.
#pragma once

#include <sys/mman.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <new>
#include <string>
#include <utility>
#include <vector>

namespace lockstep {

// The kernel's transparent huge page mode: "always", "madvise", "never", or
// "unavailable" (no such file).
inline std::string huge_page_mode() {
  std::FILE* f = std::fopen("/sys/kernel/mm/transparent_hugepage/enabled", "r");
  if (!f) return "unavailable";
  char line[128] = {};
  const bool read = std::fgets(line, sizeof line, f) != nullptr;
  std::fclose(f);
  // "always [madvise] never": the word in brackets.
  const char* a = read ? std::strchr(line, '[') : nullptr;
  const char* b = a ? std::strchr(a, ']') : nullptr;
  if (!b) return "unavailable";
  return std::string(a + 1, b);
}

// Whether large buffers are advised onto huge pages in this process (the mode
// is always or madvise and LOCKSTEP_HUGE_PAGES is not 0). Decided once per
// copy of this code (the same answer in every copy of a process).
inline bool huge_pages_used() {
  static const bool used = [] {
    const char* e = std::getenv("LOCKSTEP_HUGE_PAGES");
    if (e && std::strcmp(e, "0") == 0) return false;
    const std::string m = huge_page_mode();
    return m == "always" || m == "madvise";
  }();
  return used;
}

// One line for --version: the mode and what lockstep does with it (core/large_buffer.cpp).
std::string huge_page_summary();

inline constexpr size_t kSpacedBytes = size_t(1) << 20;  // 1 MiB: placed on a page
inline constexpr size_t kHugeBytes = size_t(1) << 20;    // 1 MiB: on huge pages

namespace large_buffer {
inline constexpr size_t kPage = 4096;
inline constexpr size_t kHugePage = size_t(2) << 20;
inline constexpr size_t kStaggerPages = 8;
inline uintptr_t align_up(uintptr_t x, size_t a) { return (x + a - 1) & ~uintptr_t(a - 1); }
// Room to start on a 2 MiB boundary (plus the stagger) and to end on one: the
// buffer's last huge page lies inside the block too.
inline size_t huge_block_bytes(size_t bytes) { return bytes + 2 * kHugePage + kStaggerPages * kPage + sizeof(char*); }
inline size_t spaced_block_bytes(size_t bytes) { return bytes + 2 * kPage; }
}  // namespace large_buffer

// bytes of memory (any size; alignment at least alignof(std::max_align_t), a
// page for kSpacedBytes and up) and its release (the same bytes). The block
// operator new gave is kept in the 8 bytes before the buffer.
inline void* allocate_large(size_t bytes) {
  using namespace large_buffer;
  if (bytes < kSpacedBytes) return ::operator new(bytes);
  if (bytes >= kHugeBytes && huge_pages_used()) {
    char* block = static_cast<char*>(::operator new(huge_block_bytes(bytes)));
    const uintptr_t b = reinterpret_cast<uintptr_t>(block);
    const uintptr_t base = align_up(b + sizeof(char*), kHugePage);
    const uintptr_t start = base + ((base / kHugePage) % kStaggerPages) * kPage;
    // The huge pages the buffer lies on, all inside the block (no other block
    // shares them). Advised before anything is written there: a 4 KiB page
    // faulted in first (the header below) would keep its whole 2 MiB on 4 KiB
    // pages. Advice only: where it fails, 4 KiB pages.
    const uintptr_t end = align_up(start + bytes, kHugePage);
    madvise(reinterpret_cast<void*>(base), end - base, MADV_HUGEPAGE);
    reinterpret_cast<char**>(start)[-1] = block;
    return reinterpret_cast<void*>(start);
  }
  char* block = static_cast<char*>(::operator new(spaced_block_bytes(bytes)));
  const uintptr_t start = align_up(reinterpret_cast<uintptr_t>(block) + sizeof(char*), kPage);
  reinterpret_cast<char**>(start)[-1] = block;
  return reinterpret_cast<void*>(start);
}

inline void free_large(void* p, size_t bytes) noexcept {
  if (!p) return;
  if (bytes < kSpacedBytes) return ::operator delete(p);
  ::operator delete(reinterpret_cast<char**>(p)[-1]);
}

// A std::allocator that places large blocks by allocate_large; construction as
// std::allocator's (a resize value-initialises).
template <class T>
struct LargeAllocator {
  using value_type = T;
  LargeAllocator() = default;
  template <class U>
  LargeAllocator(const LargeAllocator<U>&) {}
  T* allocate(size_t n) {
    if (n > size_t(-1) / 2 / sizeof(T)) throw std::bad_array_new_length();
    return static_cast<T*>(allocate_large(n * sizeof(T)));
  }
  void deallocate(T* p, size_t n) noexcept { free_large(p, n * sizeof(T)); }
  template <class U>
  bool operator==(const LargeAllocator<U>&) const {
    return true;
  }
};

// The same placement, and new elements left uninitialised (value-initialising
// a 256 MB frame is a whole extra pass over memory): for buffers whose every
// element is written before it is read.
template <class T>
struct NoInitAllocator : LargeAllocator<T> {
  template <class U>
  struct rebind {
    using other = NoInitAllocator<U>;
  };
  NoInitAllocator() = default;
  template <class U>
  NoInitAllocator(const NoInitAllocator<U>&) {}
  template <class U>
  void construct(U* p) noexcept {
    ::new (static_cast<void*>(p)) U;
  }
  template <class U, class... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
};

// A large scratch buffer whose every element is written before it is read.
template <class T>
using UninitVector = std::vector<T, NoInitAllocator<T>>;

}  // namespace lockstep
