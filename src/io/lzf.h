#pragma once
// LZF decompression (Marc Lehmann's liblzf format), for PCD files written
// with DATA binary_compressed.
//
// An LZF stream is a sequence of items, each starting with a control byte c:
//   - c < 32: a literal run: the next c + 1 bytes are copied as they are;
//   - c >= 32: a back-reference: length L = c >> 5 (when L is 7, the next
//     byte is added to it), distance D = ((c & 31) << 8 | the next byte) + 1;
//     the L + 2 bytes that start D bytes before the end of the output so
//     far are appended, one at a time, so a reference may overlap what it
//     writes (a run repeats its pattern).
// There is no header, no checksum and no end marker: the caller knows both
// sizes (PCD stores them before the stream).

#include <cstddef>
#include <span>
#include <string>
#include <string_view>

namespace recon::io::detail {

/// The most one byte of LZF stream can become: a 3-byte back-reference
/// copies at most 7 + 255 + 2 = 264 bytes, so the output is at most 88
/// times the input. A caller sizes no buffer beyond this from a header.
inline constexpr std::size_t lzf_max_expansion = 88;

/// What went wrong, and at which byte of the stream (0 when all went well).
struct LzfResult {
  std::string problem;     ///< empty: `output` was filled exactly
  std::size_t offset = 0;  ///< byte of `input` where the problem was found
  [[nodiscard]] bool ok() const { return problem.empty(); }
};

/// Decompresses all of `input` into `output`, which must be exactly the size
/// of the decompressed data. Refuses, without writing outside `output`:
/// an item cut off by the end of the input ("truncated"), a back-reference
/// to before the start of the output, an item that would write beyond the
/// end of `output`, and a stream that ends before `output` is full.
[[nodiscard]] LzfResult lzf_decompress(std::string_view input, std::span<char> output);

}  // namespace recon::io::detail
