// What the study programs print and write with: numbers in table cells, tables, lists of options,
// the search for a largest stable time step, and the output folder that remembers its files.
#pragma once

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace gpl::study {

/// The hooks the program is linked with ("solutions", "assignments", "reference"): variant_name.cpp.
extern const char* const kHookVariant;

/// x in scientific notation; "-" for NaN (not measured), "blew up" for an infinity.
inline std::string sci(double x, int digits = 2) {
    if (std::isnan(x)) return "-";
    if (std::isinf(x)) return "blew up";
    std::ostringstream out;
    out << std::scientific << std::setprecision(digits) << x;
    return out.str();
}

inline std::string fixed(double x, int digits) {
    std::ostringstream out;
    out << std::fixed << std::setprecision(digits) << x;
    return out.str();
}

/// s padded with spaces to a table column of `width` characters (at least one space after it).
inline std::string pad(const std::string& s, std::size_t width) {
    return s.size() >= width ? s + " " : s + std::string(width - s.size(), ' ');
}

/// One row of a table: each cell padded to its column's width.
inline void row(const std::vector<std::string>& cells, const std::vector<std::size_t>& widths) {
    for (std::size_t c = 0; c < cells.size(); ++c) std::cout << pad(cells[c], widths[c]);
    std::cout << std::endl;
}

/// The items of a comma-separated list, empty ones left out.
inline std::vector<std::string> split(const std::string& list) {
    std::vector<std::string> out;
    std::stringstream in(list);
    for (std::string item; std::getline(in, item, ',');) {
        if (!item.empty()) out.push_back(item);
    }
    return out;
}

/// The largest time step h for which stableAt(h) holds, to within `precision` (relative): bracketed
/// from `start` (doubled while stable, up to `high`; halved while not, down to `low`), then bisected
/// on log h. +infinity when `high` is stable, NaN when `low` is not. The last call of stableAt is at
/// the smallest unstable step found, so that what it records is that step's failure.
template <class StableAt>
double largestStable(double start, double low, double high, double precision, StableAt&& stableAt) {
    double stable = 0.0, unstable = 0.0;
    for (double h = start;;) {
        if (stableAt(h)) {
            stable = h;
            if (unstable > 0.0) break;
            if (h >= high) return std::numeric_limits<double>::infinity();
            h = std::min(2.0 * h, high);
        } else {
            unstable = h;
            if (stable > 0.0) break;
            if (h <= low) return std::nan("");
            h = std::max(0.5 * h, low);
        }
    }
    while (unstable / stable > 1.0 + precision) {
        const double mid = std::sqrt(stable * unstable);
        (stableAt(mid) ? stable : unstable) = mid;
    }
    stableAt(unstable);
    return stable;
}

/// The folder a study writes to (created when missing); open() throws std::runtime_error when a
/// file cannot be written.
class Output {
public:
    explicit Output(std::filesystem::path dir) : dir_(std::move(dir)) { std::filesystem::create_directories(dir_); }
    std::ofstream open(const std::string& name) {
        std::ofstream f(dir_ / name);
        if (!f) throw std::runtime_error("cannot write " + (dir_ / name).string());
        f << std::setprecision(10);
        written_.push_back(name);
        return f;
    }
    const std::vector<std::string>& written() const { return written_; }

private:
    std::filesystem::path dir_;
    std::vector<std::string> written_;
};

}  // namespace gpl::study
