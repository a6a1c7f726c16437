// lockstep optimized: a vector mask's bits as bytes, eight at a time.
//
// bits_to_bytes(bits): byte l of the result is bit l of `bits` (0 or 1).
// Each byte of the replicated byte picks its own bit; adding 0x7f to a byte
// carries into its top bit exactly when the picked bit is set. A mask stored
// with hn::StoreMaskBits becomes one byte a lane by one multiply and three
// logic operations instead of a loop over the lanes.
#pragma once

#include <cstdint>

namespace lockstep::opt {

inline uint64_t bits_to_bytes(uint64_t bits) {
  const uint64_t picked = ((bits & 0xff) * 0x0101010101010101ull) & 0x8040201008040201ull;
  return ((picked + 0x7f7f7f7f7f7f7f7full) >> 7) & 0x0101010101010101ull;
}

}  // namespace lockstep::opt
