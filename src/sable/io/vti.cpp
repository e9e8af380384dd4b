#include "sable/io/vti.hpp"

#include <fmt/format.h>

#include <iterator>

#include "sable/core/error.hpp"
#include "sable/io/atomic_file.hpp"
#include "sable/io/vtk_xml.hpp"

namespace sable {

namespace {

void check(const VtiImage& im) {
  for (int a = 0; a < 3; ++a)
    if (im.points[static_cast<std::size_t>(a)] < 1)
      throw InputError(
          fmt::format("vti: the image needs at least one point per axis (axis {} has {})", a,
                      im.points[static_cast<std::size_t>(a)]));
  for (const VtiArray& arr : im.point_data) {
    if (arr.components < 1)
      throw InputError(fmt::format("vti: array '{}' has {} components", arr.name, arr.components));
    const std::size_t want = static_cast<std::size_t>(arr.components) * im.size();
    if (arr.values.size() != want)
      throw InputError(fmt::format("vti: array '{}' holds {} values, expected {} ({} points x {})",
                                   arr.name, arr.values.size(), want, im.size(), arr.components));
  }
}

std::string attribute(const char* key, const std::string& value) {
  return value.empty() ? std::string() : fmt::format(" {}=\"{}\"", key, value);
}

void write_vti_pieces(const VtiImage& im, const PutText& put, VtkEncoding encoding) {
  check(im);
  write_vtk_xml(put, encoding, "ImageData", [&](VtkXmlWriter& s) {
    const auto& p = im.points;
    const std::string extent = fmt::format("0 {} 0 {} 0 {}", p[0] - 1, p[1] - 1, p[2] - 1);
    // Origin and spacing in shortest round-trip form: the grid reads back bit for bit.
    s.text(
        "<ImageData WholeExtent=\"{}\" Origin=\"{} {} {}\" Spacing=\"{} {} {}\">\n"
        "<Piece Extent=\"{}\">\n<PointData{}{}{}>\n",
        extent, im.origin[0], im.origin[1], im.origin[2], im.spacing[0], im.spacing[1],
        im.spacing[2], extent, attribute("Scalars", im.scalars), attribute("Vectors", im.vectors),
        attribute("Tensors", im.tensors));
    // ASCII: 12 significant digits: fields are averages, far less precise than that, and sums
    // read back (mass, virial) stay exact to 1e-12.
    constexpr int kDigits = 12;
    for (const VtiArray& arr : im.point_data)
      s.real_array(
          arr.name, arr.components, arr.values.size(), [&](std::size_t k) { return arr.values[k]; },
          kDigits);
    s.text("</PointData>\n<CellData>\n</CellData>\n</Piece>\n</ImageData>\n");
  });
}

}  // namespace

std::string vti_text(const VtiImage& image, VtkEncoding encoding) {
  std::string out;
  write_vti_pieces(
      image, [&](const char* data, std::size_t size) { out.append(data, size); }, encoding);
  return out;
}

void write_vti(const VtiImage& image, const std::string& path, VtkEncoding encoding) {
  write_pieces_atomic(path, [&](const PutText& put) { write_vti_pieces(image, put, encoding); });
}

}  // namespace sable
