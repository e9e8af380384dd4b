// h5::File::write_rows: a process's rows of a dataset, anywhere in it and in any order (what
// each process of a decomposed run writes of a snapshot, src/sable/mpi/mpi_snapshot.cpp). One
// process here: the rows land where they are named, in the order given, the others hold the
// fill value; every check is exact (values are copied, never computed).
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "sable/io/hdf5_file.hpp"

namespace {

namespace fs = std::filesystem;
using sable::h5::File;

std::string scratch(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("sable_h5rows_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return (dir / name).string();
}

TEST(Hdf5Rows, RowsLandWhereNamedInTheOrderGivenTheRestHoldTheFill) {
  const std::string path = scratch("rows.h5");
  {
    File f = File::create(path, "test file");
    // Rows 4, 0 and 2 of a 5 x 2 dataset, given in that order.
    const std::vector<double> data{40.0, 41.0, 0.5, 1.5, 20.0, 21.0};
    f.write_rows("/a/matrix", data.data(), {4, 0, 2}, 5, 2, -1.0);
    const std::vector<std::uint32_t> ids{7, 9};
    f.write_rows("/a/column", ids.data(), {3, 1}, 6, 0, std::uint32_t{0xffffffff});
    f.close();
  }
  const File f = File::open(path, "test file");
  EXPECT_EQ(f.read<double>("/a/matrix", 2),
            (std::vector<double>{0.5, 1.5, -1.0, -1.0, 20.0, 21.0, -1.0, -1.0, 40.0, 41.0}));
  EXPECT_EQ(f.read<std::uint32_t>("/a/column", 0),
            (std::vector<std::uint32_t>{0xffffffff, 9, 0xffffffff, 7, 0xffffffff, 0xffffffff}));
  fs::remove_all(fs::path(path).parent_path());
}

TEST(Hdf5Rows, NoRowsHereGivesAllFillAndEmptyDatasetsStayEmpty) {
  const std::string path = scratch("none.h5");
  {
    File f = File::create(path, "test file");
    f.write_rows<double>("/none", nullptr, {}, 3, 0, 2.5);
    f.write_rows<double>("/empty", nullptr, {}, 0, 3, 0.0);
    f.close();
  }
  const File f = File::open(path, "test file");
  EXPECT_EQ(f.read<double>("/none", 0), (std::vector<double>{2.5, 2.5, 2.5}));
  EXPECT_EQ(f.shape("/empty").rows, 0u);
  EXPECT_EQ(f.shape("/empty").cols, 3u);
  fs::remove_all(fs::path(path).parent_path());
}

TEST(Hdf5Rows, ARowPastTheDatasetIsRefused) {
  const std::string path = scratch("past.h5");
  File f = File::create(path, "test file");
  const std::vector<double> data{1.0};
  // A share that names a row the totals do not hold is a bug of the caller's numbering.
  EXPECT_THROW(f.write_rows("/x", data.data(), {3}, 3, 0, 0.0), std::logic_error);
  f.close();
  fs::remove_all(fs::path(path).parent_path());
}

}  // namespace
