// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
// The index of the value nearest to x in log x, in an ascending list of positive values: bisection on the
// geometric midpoints sqrt(v[i] v[i + 1]) (x below the first midpoint: 0; above the last: n - 1).
// Any thread; no allocation. n <= 0: -1.

#include <cmath>

namespace ameoto {

inline int nearest_in_log(const double* ascending, int n, double x) {
    if (n <= 0) return -1;
    int lo = 0, hi = n - 1;
    while (lo < hi) {
        const int mid = (lo + hi) / 2;
        if (x < std::sqrt(ascending[mid] * ascending[mid + 1])) {
            hi = mid;
        } else {
            lo = mid + 1;
        }
    }
    return lo;
}

}  // namespace ameoto
