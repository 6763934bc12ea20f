#pragma once
// A 64-bit mixing function (splitmix64's finaliser): every input bit moves
// about half the output bits. For choices that must look random yet depend
// only on their input (a point's position, a patch's key), so that any
// part of a cloud makes them as the whole does.

#include <cstdint>

namespace recon::detail {

[[nodiscard]] constexpr std::uint64_t mix64(std::uint64_t x) {
  x ^= x >> 30;
  x *= 0xbf58476d1ce4e5b9ULL;
  x ^= x >> 27;
  x *= 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

}  // namespace recon::detail
