#include "sable/io/xdmf.hpp"

#include <fmt/format.h>

#include <iterator>

#include "sable/io/atomic_file.hpp"

namespace sable {

namespace {

// An HDF5 dataset of `rows` x `cols` (cols 1: a plain array) of XDMF's `type` and byte size.
std::string hdf_item(const XdmfSnapshot& s, const char* dataset, std::size_t cols, const char* type,
                     int bytes) {
  const std::string dims =
      cols == 1 ? fmt::format("{}", s.grains) : fmt::format("{} {}", s.grains, cols);
  return fmt::format(
      "<DataItem Dimensions=\"{}\" NumberType=\"{}\" Precision=\"{}\" "
      "Format=\"HDF\">{}:{}</DataItem>",
      dims, type, bytes, s.h5_name, dataset);
}

}  // namespace

std::string xdmf_text(const XdmfSnapshot& s) {
  fmt::memory_buffer b;
  auto out = std::back_inserter(b);
  const auto d = static_cast<std::size_t>(s.dimension);
  // Times in shortest round-trip form: the snapshot's own time, to the bit.
  fmt::format_to(out,
                 "<?xml version=\"1.0\" ?>\n"
                 "<Xdmf Version=\"3.0\">\n<Domain>\n<Grid Name=\"grains\" GridType=\"Uniform\">\n"
                 "<Time Value=\"{}\"/>\n"
                 "<Topology TopologyType=\"Polyvertex\" NumberOfElements=\"{}\" "
                 "NodesPerElement=\"1\"/>\n"
                 "<Geometry GeometryType=\"{}\">{}</Geometry>\n",
                 s.time, s.grains, s.dimension == 2 ? "XY" : "XYZ",
                 hdf_item(s, "/particles/x", d, "Float", 8));
  const auto attribute = [&](const char* name, const std::string& item, bool vector) {
    fmt::format_to(out,
                   "<Attribute Name=\"{}\" AttributeType=\"{}\" Center=\"Node\">{}</Attribute>\n",
                   name, vector ? "Vector" : "Scalar", item);
  };
  // The id's index: column 0 of the (grains x 2) dataset /particles/id (index, generation).
  attribute("id",
            fmt::format("<DataItem ItemType=\"HyperSlab\" Dimensions=\"{} 1\" Type=\"HyperSlab\">"
                        "<DataItem Dimensions=\"3 2\" Format=\"XML\">0 0 1 1 {} 1</DataItem>{}"
                        "</DataItem>",
                        s.grains, s.grains, hdf_item(s, "/particles/id", 2, "UInt", 4)),
            false);
  attribute("radius", hdf_item(s, "/particles/radius", 1, "Float", 8), false);
  attribute("mass", hdf_item(s, "/particles/mass", 1, "Float", 8), false);
  attribute("material", hdf_item(s, "/particles/material", 1, "UInt", 2), false);
  attribute("flags", hdf_item(s, "/particles/flags", 1, "UChar", 1), false);
  // 2D: velocity and force of 2 components, the spin a scalar (about z).
  attribute("velocity", hdf_item(s, "/particles/v", d, "Float", 8), true);
  attribute("angular_velocity", hdf_item(s, "/particles/w", d == 3 ? 3 : 1, "Float", 8), d == 3);
  attribute("force", hdf_item(s, "/particles/f", d, "Float", 8), true);
  fmt::format_to(out, "</Grid>\n</Domain>\n</Xdmf>\n");
  return fmt::to_string(b);
}

void write_xdmf(const XdmfSnapshot& s, const std::string& path) {
  write_text_atomic(path, xdmf_text(s));
}

}  // namespace sable
