// SPDX-License-Identifier: GPL-3.0-or-later
#include "engine/core/fft.hpp"

#include <stdexcept>
#include <utility>

#include "engine/core/physical_constants.hpp"

namespace ameoto {

void fft_in_place(std::vector<std::complex<double>>& a) {
    const std::size_t n = a.size();
    if (n == 0 || (n & (n - 1)) != 0) throw std::invalid_argument("fft_in_place: the size must be a power of two");
    for (std::size_t i = 1, j = 0; i < n; ++i) {   // bit-reversal permutation
        std::size_t bit = n >> 1;
        for (; j & bit; bit >>= 1) j ^= bit;
        j ^= bit;
        if (i < j) std::swap(a[i], a[j]);
    }
    for (std::size_t len = 2; len <= n; len <<= 1) {
        const std::complex<double> w = std::polar(1.0, -2.0 * constants::pi / static_cast<double>(len));
        for (std::size_t i = 0; i < n; i += len) {
            std::complex<double> wk = 1.0;
            for (std::size_t k = 0; k < len / 2; ++k) {
                const std::complex<double> u = a[i + k], v = a[i + k + len / 2] * wk;
                a[i + k] = u + v;
                a[i + k + len / 2] = u - v;
                wk *= w;
            }
        }
    }
}

}  // namespace ameoto
