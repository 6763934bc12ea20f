#pragma once
// A LAS file written from the specification (LAS 1.0 to 1.4, point data
// record formats 0 to 10), for the io tests: each record is built from the
// parts the specification lists for its format, not from the reader's
// tables, and every byte recon does not read is filled with a pattern, so a
// reader that looked at the wrong place would see it.

#include "io/io_test_helpers.h"

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace recon::io::testing {

using Rgb16 = std::array<std::uint16_t, 3>;

struct LasPoint {
  std::array<std::int32_t, 3> xyz{};
  Rgb16 rgb{};
};

/// A LAS file as the specification lays it out.
struct LasFile {
  unsigned minor = 2;
  unsigned format = 0;
  std::array<double, 3> scale = {0.01, 0.01, 0.01};
  std::array<double, 3> offset = {0.0, 0.0, 0.0};
  std::vector<LasPoint> points;
  std::size_t extra_bytes = 0;        ///< after each record's fields
  std::size_t vlr_bytes = 0;          ///< between the header and the points
  bool legacy_count = true;           ///< the 32-bit count at byte 107
  bool count_64 = true;               ///< 1.4: the 64-bit count at byte 247
  std::uint8_t format_byte_bits = 0;  ///< or-ed into the format byte (laszip's compression bits)

  [[nodiscard]] static std::size_t header_size(unsigned minor_version) {
    return minor_version <= 2 ? 227 : minor_version == 3 ? 235 : 375;
  }
  [[nodiscard]] bool has_gps_time() const { return format == 1 || format >= 3; }
  [[nodiscard]] bool has_rgb() const {
    return format == 2 || format == 3 || format == 5 || format == 7 || format == 8 || format == 10;
  }
  [[nodiscard]] bool has_nir() const { return format == 8 || format == 10; }
  [[nodiscard]] bool has_wave_packet() const { return format == 4 || format == 5 || format == 9 || format == 10; }

  /// The record as the specification lists its fields; its size must be the format's.
  [[nodiscard]] std::string record(const LasPoint& p) const {
    Bytes r;
    for (const std::int32_t c : p.xyz) r.put(c);
    r.put<std::uint16_t>(0xA1A2);  // intensity
    if (format <= 5) {
      r.put<std::uint8_t>(0xB1).put<std::uint8_t>(0xB2);  // return bits, classification
      r.put<std::int8_t>(-7).put<std::uint8_t>(0xB3);     // scan angle rank, user data
      r.put<std::uint16_t>(0xC1C2);                       // point source ID
      if (has_gps_time()) r.put(123456.789);
    } else {
      r.put<std::uint8_t>(0xB1).put<std::uint8_t>(0xB2).put<std::uint8_t>(0xB3).put<std::uint8_t>(0xB4);
      r.put<std::int16_t>(-1234).put<std::uint16_t>(0xC1C2);  // scan angle, point source ID
      r.put(123456.789);                                      // GPS time
    }
    if (has_rgb()) {
      for (const std::uint16_t c : p.rgb) r.put(c);
    }
    if (has_nir()) r.put<std::uint16_t>(0xD1D2);
    if (has_wave_packet()) {
      r.put<std::uint8_t>(1).put<std::uint64_t>(0xE1E2E3E4E5E6E7E8ULL).put<std::uint32_t>(0xF1F2F3F4U);
      r.put(0.5F).put(1.5F).put(2.5F).put(3.5F);
    }
    return r.str() + std::string(extra_bytes, '\xEE');
  }

  [[nodiscard]] std::size_t record_length() const { return record(LasPoint{}).size(); }

  [[nodiscard]] std::string bytes() const {
    Bytes h;
    h.text("LASF");
    h.put<std::uint16_t>(0).put<std::uint16_t>(0);  // file source ID, global encoding
    h.put<std::uint32_t>(0).put<std::uint16_t>(0).put<std::uint16_t>(0).text(std::string(8, '\0'));  // GUID
    h.put<std::uint8_t>(1).put(static_cast<std::uint8_t>(minor));
    h.text(std::string(32, 's')).text(std::string(32, 'g'));  // system identifier, generating software
    h.put<std::uint16_t>(100).put<std::uint16_t>(2024);       // creation day and year
    const std::size_t size = header_size(minor);
    h.put(static_cast<std::uint16_t>(size));
    h.put(static_cast<std::uint32_t>(size + vlr_bytes));  // offset to point data
    h.put<std::uint32_t>(vlr_bytes != 0 ? 1 : 0);         // number of VLRs
    h.put(static_cast<std::uint8_t>(format | format_byte_bits));
    h.put(static_cast<std::uint16_t>(record_length()));
    h.put(static_cast<std::uint32_t>(legacy_count ? points.size() : 0));
    for (int r = 0; r < 5; ++r) h.put<std::uint32_t>(0);  // points by return
    for (const double s : scale) h.put(s);
    for (const double o : offset) h.put(o);
    for (int k = 0; k < 6; ++k) h.put(0.0);   // max and min x, y, z
    if (minor >= 3) h.put<std::uint64_t>(0);  // start of waveform data
    if (minor >= 4) {
      h.put<std::uint64_t>(0).put<std::uint32_t>(0);  // first EVLR, number of EVLRs
      h.put(static_cast<std::uint64_t>(count_64 ? points.size() : 0));
      for (int r = 0; r < 15; ++r) h.put<std::uint64_t>(0);
    }
    EXPECT_EQ(h.size(), size);
    std::string file = h.str() + std::string(vlr_bytes, '\x77');
    for (const LasPoint& p : points) file += record(p);
    return file;
  }
};

}  // namespace recon::io::testing
