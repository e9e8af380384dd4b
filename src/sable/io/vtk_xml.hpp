// The data arrays of VTK's XML formats (.vtp, .vti), in one of three encodings.
//
// - kBinary (the default): every array's bytes in one <AppendedData encoding="raw"> section
//   at the end of the file, each preceded by its byte count (UInt64: header_type="UInt64"),
//   little-endian as this machine's memory is. No base64: a Float64 takes 8 bytes instead of
//   the 10-17 characters of its text, and is written by a memcpy instead of a conversion.
// - kZlib: the same section, each array cut into 32 KiB blocks compressed by zlib (VTK's
//   vtkZLibDataCompressor layout: a header of UInt64 [blocks, block size, size of the last
//   partial block or 0, compressed size of each block], then the blocks).
// - kAscii: the values as text inside their <DataArray> (readable, and what every XML reader
//   takes without decoding; 9 significant digits for Float64, see real_array).
// ParaView reads all three. Readers in Python: scripts/vtkxml.py.
//
// write_vtk_xml() makes one file: the caller's `body` writes the XML elements of the data set
// (text()) and its arrays (real_array, int_array), and the writer adds the declaration, the
// <VTKFile> element and the appended section. Under kBinary `body` runs twice: once for the
// XML, each array's offset in the appended section known from its size alone, then once to
// stream the arrays' bytes after the XML, 64 KiB at a time, nothing held. Under kZlib the
// compressed arrays are held until the XML is done (their sizes are the offsets); under
// kAscii everything is text, in one run of `body`.
#pragma once

#include <fmt/format.h>

#include <cstdint>
#include <cstring>
#include <functional>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "sable/io/atomic_file.hpp"

namespace sable {

enum class VtkEncoding : std::uint8_t { kBinary, kZlib, kAscii };

// "binary", "zlib" or "ascii" (the spellings of [output] vtk_format and --vtk-format).
std::string_view vtk_encoding_name(VtkEncoding e);
// The encoding named `name`; throws InputError naming `where` and the three spellings.
VtkEncoding parse_vtk_encoding(std::string_view name, std::string_view where);

// VTK's name for a C++ arithmetic type (Float64, Int64, Int32, UInt8, ...).
template <class T>
constexpr const char* vtk_type_name() {
  if constexpr (std::is_same_v<T, double>) return "Float64";
  if constexpr (std::is_same_v<T, float>) return "Float32";
  if constexpr (std::is_same_v<T, std::int64_t>) return "Int64";
  if constexpr (std::is_same_v<T, std::int32_t>) return "Int32";
  if constexpr (std::is_same_v<T, std::uint64_t>) return "UInt64";
  if constexpr (std::is_same_v<T, std::uint32_t>) return "UInt32";
  if constexpr (std::is_same_v<T, std::uint8_t>) return "UInt8";
}

class VtkXmlWriter {
 public:
  VtkXmlWriter(const VtkXmlWriter&) = delete;
  VtkXmlWriter& operator=(const VtkXmlWriter&) = delete;

  VtkEncoding encoding() const { return enc_; }

  // XML text, as it comes.
  template <class... Args>
  void text(fmt::format_string<Args...> f, Args&&... args) {
    if (pass_ == Pass::kData) return;
    fmt::format_to(std::back_inserter(buf_), f, std::forward<Args>(args)...);
    spill();
  }

  // A Float64 DataArray of `count` values, `comps` per tuple; value(k) is the k-th. ASCII: 9
  // significant digits (`digits` to change it): every value exact to float precision,
  // doubles within 5e-9 relative. The binary encodings store the doubles' bits.
  template <class Value>
  void real_array(std::string_view name, int comps, std::size_t count, Value value,
                  int digits = 9) {
    array<double>(name, comps, count, value, digits);
  }

  // An integer DataArray of type T (one component) of `count` values.
  template <class T, class Value>
  void int_array(std::string_view name, std::size_t count, Value value) {
    array<T>(name, 1, count, value, 0);
  }

 private:
  friend void write_vtk_xml(const PutText& put, VtkEncoding encoding, std::string_view type,
                            const std::function<void(VtkXmlWriter&)>& body);
  enum class Pass : std::uint8_t { kXml, kData };
  VtkXmlWriter(const PutText& put, VtkEncoding encoding) : put_(put), enc_(encoding) {}

  template <class T, class Value>
  void array(std::string_view name, int comps, std::size_t count, Value value, int digits) {
    if (enc_ == VtkEncoding::kAscii) return ascii_array<T>(name, comps, count, value, digits);
    if (pass_ == Pass::kData) {  // kBinary's second run: the byte count, then the bytes
      put_u64(count * sizeof(T));
      for (std::size_t k = 0; k < count; ++k) {
        const T v = static_cast<T>(value(k));
        const auto* bytes = reinterpret_cast<const char*>(&v);
        buf_.append(bytes, bytes + sizeof(T));
        spill();
      }
      return;
    }
    text(
        "<DataArray type=\"{}\" Name=\"{}\" NumberOfComponents=\"{}\" format=\"appended\" "
        "offset=\"{}\"/>\n",
        vtk_type_name<T>(), name, comps, offset_);
    if (enc_ == VtkEncoding::kBinary) {
      offset_ += sizeof(std::uint64_t) + count * sizeof(T);
      return;
    }
    raw_.resize(count * sizeof(T));
    for (std::size_t k = 0; k < count; ++k) {
      const T v = static_cast<T>(value(k));
      std::memcpy(raw_.data() + k * sizeof(T), &v, sizeof(T));
    }
    compress_raw();
    offset_ = zipped_.size();
  }

  template <class T, class Value>
  void ascii_array(std::string_view name, int comps, std::size_t count, Value value, int digits) {
    text("<DataArray type=\"{}\" Name=\"{}\" NumberOfComponents=\"{}\" format=\"ascii\">\n",
         vtk_type_name<T>(), name, comps);
    // Rows of one tuple (reals) or 16 values (integers), as a reader would lay them out.
    const std::size_t row = std::is_floating_point_v<T> ? static_cast<std::size_t>(comps) : 16;
    for (std::size_t k = 0; k < count; ++k) {
      if constexpr (std::is_floating_point_v<T>)
        fmt::format_to(std::back_inserter(buf_), "{:.{}g}", static_cast<double>(value(k)), digits);
      else
        fmt::format_to(std::back_inserter(buf_), "{}", static_cast<std::int64_t>(value(k)));
      buf_.push_back((k + 1) % row == 0 || k + 1 == count ? '\n' : ' ');
      spill();
    }
    text("</DataArray>\n");
  }

  void put_u64(std::uint64_t v);
  void spill(bool all = false);
  void compress_raw();  // raw_ onto zipped_: VTK's block header, then the zlib blocks

  static constexpr std::size_t kPiece = std::size_t{1} << 16;
  const PutText& put_;
  VtkEncoding enc_;
  Pass pass_ = Pass::kXml;
  std::uint64_t offset_ = 0;  // the next array's offset in the appended section
  fmt::memory_buffer buf_;
  std::vector<unsigned char> raw_;     // kZlib: one array's bytes
  std::vector<unsigned char> zipped_;  // kZlib: the appended section after its '_'
};

// Write one VTK XML file of data-set `type` (PolyData, ImageData) through `put`; `body` must
// write the same elements and arrays each time it runs and do nothing else.
void write_vtk_xml(const PutText& put, VtkEncoding encoding, std::string_view type,
                   const std::function<void(VtkXmlWriter&)>& body);

}  // namespace sable
