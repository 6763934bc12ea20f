#include "lzf.h"

#include <cstdint>
#include <cstring>

namespace recon::io::detail {

LzfResult lzf_decompress(std::string_view input, std::span<char> output) {
  std::size_t in = 0;   // next byte of the stream
  std::size_t out = 0;  // bytes written so far
  const auto byte_at = [&](std::size_t i) { return static_cast<std::uint8_t>(input[i]); };
  while (in < input.size()) {
    const std::size_t item = in;
    const std::size_t control = byte_at(in++);
    if (control < 32) {  // literal run
      const std::size_t length = control + 1;
      if (length > input.size() - in)
        return {"a literal run of " + std::to_string(length) + " bytes is cut off by the end of the data", item};
      if (length > output.size() - out)
        return {"a literal run goes beyond the " + std::to_string(output.size()) + " bytes of decompressed data", item};
      std::memcpy(output.data() + out, input.data() + in, length);
      in += length;
      out += length;
      continue;
    }
    std::size_t length = control >> 5;
    if (length == 7) {
      if (in == input.size()) return {"a back-reference is cut off by the end of the data", item};
      length += byte_at(in++);
    }
    if (in == input.size()) return {"a back-reference is cut off by the end of the data", item};
    const std::size_t distance = (((control & 31U) << 8) | byte_at(in++)) + 1;
    length += 2;
    if (distance > out)
      return {"a back-reference " + std::to_string(distance) +
                  " bytes back reaches before the start of the decompressed data (at its byte " + std::to_string(out) +
                  ")",
              item};
    if (length > output.size() - out)
      return {"a back-reference goes beyond the " + std::to_string(output.size()) + " bytes of decompressed data",
              item};
    // Byte by byte: when distance < length the copy reads what it has just written.
    for (std::size_t k = 0; k < length; ++k, ++out) output[out] = output[out - distance];
  }
  if (out != output.size())
    return {"the data decompresses to " + std::to_string(out) + " bytes, not the " + std::to_string(output.size()) +
                " the header gives",
            in};
  return {};
}

}  // namespace recon::io::detail
