#include "sable/io/vtk_xml.hpp"

#include <zlib.h>

#include <algorithm>
#include <bit>
#include <limits>

#include "sable/core/error.hpp"

namespace sable {

// The files say byte_order="LittleEndian" and copy memory as it is.
static_assert(std::endian::native == std::endian::little, "VTK output assumes little-endian");

namespace {

// zlib's block of VTK's compressor: small enough that a reader inflates a piece at a time,
// large enough that the per-block header and zlib's own start cost nothing.
constexpr std::size_t kBlock = std::size_t{1} << 15;
// zlib's level 1 ("best speed"): on a grains frame it keeps most of level 6's reduction for a
// fraction of its time (docs/BENCHMARKS.md, BM_VtkFrame).
constexpr int kLevel = 1;

void store_u64(std::vector<unsigned char>& out, std::size_t at, std::uint64_t v) {
  std::memcpy(out.data() + at, &v, sizeof v);
}

}  // namespace

std::string_view vtk_encoding_name(VtkEncoding e) {
  switch (e) {
    case VtkEncoding::kBinary:
      return "binary";
    case VtkEncoding::kZlib:
      return "zlib";
    case VtkEncoding::kAscii:
      return "ascii";
  }
  return "?";
}

VtkEncoding parse_vtk_encoding(std::string_view name, std::string_view where) {
  for (VtkEncoding e : {VtkEncoding::kBinary, VtkEncoding::kZlib, VtkEncoding::kAscii})
    if (name == vtk_encoding_name(e)) return e;
  throw InputError(fmt::format(
      "{}: \"{}\" is not a VTK format; expected \"binary\" (raw appended data, the default), "
      "\"zlib\" (compressed) or \"ascii\"",
      where, name));
}

void VtkXmlWriter::put_u64(std::uint64_t v) {
  const auto* bytes = reinterpret_cast<const char*>(&v);
  buf_.append(bytes, bytes + sizeof v);
}

void VtkXmlWriter::spill(bool all) {
  if (buf_.size() < kPiece && !all) return;
  put_(buf_.data(), buf_.size());
  buf_.clear();
}

void VtkXmlWriter::compress_raw() {
  const std::size_t at = zipped_.size();
  const std::size_t blocks = (raw_.size() + kBlock - 1) / kBlock;
  const std::size_t header = (3 + blocks) * sizeof(std::uint64_t);
  zipped_.resize(at + header);
  store_u64(zipped_, at, blocks);
  store_u64(zipped_, at + 8, kBlock);
  store_u64(zipped_, at + 16, raw_.size() % kBlock);  // 0: the last block is full
  for (std::size_t b = 0; b < blocks; ++b) {
    const std::size_t from = b * kBlock, size = std::min(kBlock, raw_.size() - from);
    uLongf bound = compressBound(static_cast<uLong>(size));
    const std::size_t start = zipped_.size();
    zipped_.resize(start + bound);
    if (compress2(zipped_.data() + start, &bound, raw_.data() + from, static_cast<uLong>(size),
                  kLevel) != Z_OK)
      throw IoError("zlib could not compress a VTK data block");
    zipped_.resize(start + bound);
    store_u64(zipped_, at + 24 + 8 * b, bound);
  }
}

void write_vtk_xml(const PutText& put, VtkEncoding encoding, std::string_view type,
                   const std::function<void(VtkXmlWriter&)>& body) {
  VtkXmlWriter w(put, encoding);
  w.text(
      "<?xml version=\"1.0\"?>\n<VTKFile type=\"{}\" version=\"1.0\" "
      "byte_order=\"LittleEndian\" header_type=\"UInt64\"{}>\n",
      type, encoding == VtkEncoding::kZlib ? " compressor=\"vtkZLibDataCompressor\"" : "");
  body(w);
  if (encoding != VtkEncoding::kAscii) {
    w.text("<AppendedData encoding=\"raw\">\n_");
    w.spill(true);
    if (encoding == VtkEncoding::kBinary) {
      w.pass_ = VtkXmlWriter::Pass::kData;
      body(w);
      w.pass_ = VtkXmlWriter::Pass::kXml;
    } else if (!w.zipped_.empty()) {
      put(reinterpret_cast<const char*>(w.zipped_.data()), w.zipped_.size());
    }
    w.text("\n</AppendedData>\n");
  }
  w.text("</VTKFile>\n");
  w.spill(true);
}

}  // namespace sable
