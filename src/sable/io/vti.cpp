#include "sable/io/vti.hpp"

#include <fmt/format.h>

#include <iterator>

#include "sable/core/error.hpp"
#include "sable/io/atomic_file.hpp"

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

}  // namespace

std::string vti_text(const VtiImage& im) {
  check(im);
  fmt::memory_buffer b;
  auto out = std::back_inserter(b);
  const auto& p = im.points;
  const std::string extent = fmt::format("0 {} 0 {} 0 {}", p[0] - 1, p[1] - 1, p[2] - 1);
  // Origin and spacing in shortest round-trip form: the grid reads back bit for bit.
  fmt::format_to(out,
                 "<?xml version=\"1.0\"?>\n"
                 "<VTKFile type=\"ImageData\" version=\"1.0\" byte_order=\"LittleEndian\">\n"
                 "  <ImageData WholeExtent=\"{}\" Origin=\"{} {} {}\" "
                 "Spacing=\"{} {} {}\">\n"
                 "    <Piece Extent=\"{}\">\n"
                 "      <PointData{}{}{}>\n",
                 extent, im.origin[0], im.origin[1], im.origin[2], im.spacing[0], im.spacing[1],
                 im.spacing[2], extent, attribute("Scalars", im.scalars),
                 attribute("Vectors", im.vectors), attribute("Tensors", im.tensors));
  for (const VtiArray& arr : im.point_data) {
    fmt::format_to(out,
                   "        <DataArray type=\"Float64\" Name=\"{}\" NumberOfComponents=\"{}\" "
                   "format=\"ascii\">\n",
                   arr.name, arr.components);
    const std::size_t c = static_cast<std::size_t>(arr.components);
    for (std::size_t k = 0; k < arr.values.size(); k += c) {
      fmt::format_to(out, "          ");
      for (std::size_t q = 0; q < c; ++q) {
        if (q > 0) fmt::format_to(out, " ");
        // 12 significant digits: fields are averages, far less precise than that, and sums
        // read back (mass, virial) stay exact to 1e-12.
        fmt::format_to(out, "{:.12g}", arr.values[k + q]);
      }
      fmt::format_to(out, "\n");
    }
    fmt::format_to(out, "        </DataArray>\n");
  }
  fmt::format_to(out,
                 "      </PointData>\n"
                 "      <CellData>\n"
                 "      </CellData>\n"
                 "    </Piece>\n"
                 "  </ImageData>\n"
                 "</VTKFile>\n");
  return fmt::to_string(b);
}

void write_vti(const VtiImage& image, const std::string& path) {
  write_text_atomic(path, vti_text(image));
}

}  // namespace sable
