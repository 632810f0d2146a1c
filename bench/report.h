// What both study programs (accuracy_main.cpp, contacts_main.cpp) print and write with: numbers
// in table cells, and the output folder that remembers the files written to it.
#pragma once

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
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
