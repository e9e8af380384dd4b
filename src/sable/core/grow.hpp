// Arrays refilled at every list rebuild, sized with headroom.
//
// A contact list grows by a few entries at each rebuild while a bed settles (the pour: from
// 57,000 to 103,000 pairs over 170 rebuilds). libstdc++'s assign(n, value) and a range insert
// into a cleared vector allocate exactly what they need when the capacity falls short, so
// every such rebuild took new memory for each array of the list, and the kernel handed its
// pages in one fault at a time: on the project's VM about 10 us per 4 KiB page, 9 ms per
// rebuild of the pour's lists, more than the neighbour search itself. Growing the capacity by
// a quarter ahead of need makes that a rare event (a handful of times in a settling), at the
// price of at most a quarter more memory for those arrays.
#pragma once

#include <cstddef>
#include <vector>

namespace sable {

// Capacity for at least n elements, with a quarter to spare when it has to grow.
template <class T, class A>
void reserve_ahead(std::vector<T, A>& v, std::size_t n) {
  if (n > v.capacity()) v.reserve(n + n / 4 + 64);
}

// v = n copies of value, in memory that is reused from one rebuild to the next.
template <class T, class A>
void assign_ahead(std::vector<T, A>& v, std::size_t n, const T& value) {
  reserve_ahead(v, n);
  v.assign(n, value);
}

}  // namespace sable
