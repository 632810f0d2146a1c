// Command-line errors, the same for every program of the lab (runner, viewer, studies): one line
// "error: --OPTION: what it expects, got 'VALUE'" on stderr and exit status 2; --help prints the
// help and exits 0. The checks below run on the option's text before CLI11 converts it, so a value
// that is not a number is reported like one out of range.
#pragma once

#include <CLI/CLI.hpp>
#include <cmath>
#include <filesystem>
#include <functional>
#include <iostream>
#include <limits>
#include <string>
#include <system_error>
#include <unistd.h>

#include "gpl/scenes.h"

namespace gpl::cli {

/// A check of an option's text: empty when good, else what the option expects.
inline CLI::Validator expects(const std::string& what, std::function<bool(const std::string&)> good) {
    return CLI::Validator(
        [what, good](std::string& text) { return good(text) ? std::string() : "expects " + what + ", got '" + text + "'"; },
        "", "");
}

/// A whole number in [min, max].
inline CLI::Validator wholeNumber(long long min, long long max = std::numeric_limits<long long>::max()) {
    std::string what = "a whole number";
    if (max == std::numeric_limits<long long>::max()) {
        what += min == 0 ? " of 0 or more" : " of " + std::to_string(min) + " or more";
    } else {
        what += " from " + std::to_string(min) + " to " + std::to_string(max);
    }
    return expects(what, [min, max](const std::string& text) {
        std::size_t used = 0;
        try {
            const long long v = std::stoll(text, &used);
            return used == text.size() && v >= min && v <= max;
        } catch (const std::exception&) {
            return false;
        }
    });
}

/// A finite number of seconds above zero.
inline CLI::Validator positiveSeconds() {
    return expects("a time in seconds above 0 (such as 0.005)", [](const std::string& text) {
        std::size_t used = 0;
        try {
            const double v = std::stod(text, &used);
            return used == text.size() && std::isfinite(v) && v > 0.0;
        } catch (const std::exception&) {
            return false;
        }
    });
}

/// Makes the folder an option names (and its parents) unless it exists. Returns "" when it is
/// there, else the one-line error: the option, what it expects, the value and why it failed.
inline std::string makeFolder(const std::string& option, const std::string& path) {
    std::error_code ec;
    if (!path.empty()) std::filesystem::create_directories(path, ec);
    if (!path.empty() && !ec && std::filesystem::is_directory(path, ec) && ::access(path.c_str(), W_OK | X_OK) == 0) {
        return "";
    }
    return option + ": expects a folder that exists or can be made, and is writable, got '" + path + "'" +
           (ec ? " (" + ec.message() + ")" : "");
}

/// One of a few words, listed in the message.
inline CLI::Validator oneOf(const std::vector<std::string>& words) {
    std::string list;
    for (std::size_t i = 0; i < words.size(); ++i) {
        list += (i == 0 ? "" : i + 1 == words.size() ? " or " : ", ") + words[i];
    }
    return expects(list, [words](const std::string& text) {
        for (const std::string& w : words) {
            if (text == w) return true;
        }
        return false;
    });
}

/// The name or key of a scene (gpl::scenes()).
inline CLI::Validator sceneName() {
    return expects("a scene name or key such as falling-sphere or 1 (./lab run --list lists them)",
                   [](const std::string& text) {
                       try {
                           scenes().find(text);
                           return true;
                       } catch (const std::exception&) {
                           return false;
                       }
                   });
}

/// Parses the command line. Returns -1 when the program goes on, else its exit status: 0 after
/// --help (printed), 2 after an error (printed as one line).
inline int parse(CLI::App& app, int argc, char** argv) {
    try {
        app.parse(argc, argv);
        return -1;
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        // A failed check names the option and what it expects; other errors (an unknown option, a
        // missing value) name the option, and --help says what there is.
        std::string message = e.what();
        for (char& c : message) {
            if (c == '\n') c = ' ';
        }
        if (dynamic_cast<const CLI::ValidationError*>(&e) == nullptr) message += " (--help lists the options)";
        std::cerr << "error: " << message << '\n';
        return 2;
    }
}

}  // namespace gpl::cli
