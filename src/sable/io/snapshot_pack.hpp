// How the arrays of a World lay out in a snapshot's datasets (io/snapshot.cpp reads them,
// io/snapshot_write.cpp writes them).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "sable/io/hdf5_file.hpp"

namespace sable::snapshot_detail {

// How one element of a per-grain array lays out as a row of doubles in a dataset.
template <class T>
struct Pack;

template <>
struct Pack<double> {
  static constexpr hsize_t cols = 1;
  static void put(double x, double* out) { out[0] = x; }
  static double get(const double* in) { return in[0]; }
};

template <int K>
struct Pack<Eigen::Matrix<double, K, 1>> {
  using T = Eigen::Matrix<double, K, 1>;
  static constexpr hsize_t cols = K;
  static void put(const T& x, double* out) {
    for (int k = 0; k < K; ++k) out[k] = x[k];
  }
  static T get(const double* in) {
    T x;
    for (int k = 0; k < K; ++k) x[k] = in[k];
    return x;
  }
};

template <>
struct Pack<Eigen::Quaterniond> {
  static constexpr hsize_t cols = 4;  // w, x, y, z
  static void put(const Eigen::Quaterniond& q, double* out) {
    out[0] = q.w();
    out[1] = q.x();
    out[2] = q.y();
    out[3] = q.z();
  }
  static Eigen::Quaterniond get(const double* in) {
    return Eigen::Quaterniond(in[0], in[1], in[2], in[3]);
  }
};

}  // namespace sable::snapshot_detail
