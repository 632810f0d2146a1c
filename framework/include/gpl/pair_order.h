// The order of things that belong to pairs of bodies (the broad phase's pairs, the friction stage's
// contacts), by pair: counted by the first body and placed in its range, then each body's few
// ordered by the second. Linear in the bodies and the things, where a comparison sort is not.
#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

namespace gpl {

/// The indices 0 .. n - 1 into `order`, sorted by (first(i), second(i)), equal pairs in the order of
/// their indices. first(i) < bodies. Afterwards [firsts[a], firsts[a + 1]) is the range of `order`
/// whose first body is a. `cursor` is a buffer (kept by the caller, so nothing is allocated again).
template <class First, class Second>
void orderByPair(std::size_t n, std::size_t bodies, First first, Second second, std::vector<std::size_t>& order,
                 std::vector<std::size_t>& firsts, std::vector<std::size_t>& cursor) {
    firsts.assign(bodies + 1, 0);
    for (std::size_t i = 0; i < n; ++i) ++firsts[first(i) + 1];
    for (std::size_t a = 0; a < bodies; ++a) firsts[a + 1] += firsts[a];
    cursor.assign(firsts.begin(), firsts.end() - 1);
    order.resize(n);
    for (std::size_t i = 0; i < n; ++i) order[cursor[first(i)]++] = i;
    const auto bySecond = [&second](std::size_t x, std::size_t y) { return second(x) < second(y); };
    for (std::size_t a = 0; a < bodies; ++a) {
        const auto begin = order.begin() + static_cast<std::ptrdiff_t>(firsts[a]);
        const auto end = order.begin() + static_cast<std::ptrdiff_t>(firsts[a + 1]);
        if (end - begin > 16) {
            std::stable_sort(begin, end, bySecond);  // a plane's or a large body's many
            continue;
        }
        for (auto k = begin + (begin != end ? 1 : 0); k < end; ++k) {  // insertion sort: a body's few
            const std::size_t moving = *k;
            auto m = k;
            for (; m > begin && bySecond(moving, *(m - 1)); --m) *m = *(m - 1);
            *m = moving;
        }
    }
}

}  // namespace gpl
