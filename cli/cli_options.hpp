// How the commands declare their options on CLI11: counts and numbers are
// read as text and checked here, so a bad value names its option and what it
// expects ("--steps: expected an integer >= 0, got '12x'") whatever CLI11's
// own wording, and every option shows its value's name in --help.
#pragma once
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "cli_support.hpp"

namespace swarmcl_cli {

// --flag N: an integer >= min; `target` is set only when the option is given.
inline CLI::Option* add_count(CLI::App& app, const std::string& flag, std::optional<uint32_t>& target,
                              uint32_t min, const std::string& help) {
    return app
        .add_option_function<std::string>(
            flag, [&target, flag, min](const std::string& text) { target = parse_count(flag.c_str(), text.c_str(), min); },
            help)
        ->type_name("N");
}

// --flag N: an integer >= min, into a value that has its default already.
inline CLI::Option* add_count(CLI::App& app, const std::string& flag, uint32_t& target, uint32_t min,
                              const std::string& help) {
    return app
        .add_option_function<std::string>(
            flag, [&target, flag, min](const std::string& text) { target = parse_count(flag.c_str(), text.c_str(), min); },
            help)
        ->type_name("N");
}

inline double parse_number(const std::string& flag, const std::string& text) {
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    if (text.empty() || *end || !std::isfinite(v)) throw Usage{flag + ": expected a number, got '" + text + "'"};
    return v;
}

// --flag X: a finite number.
inline CLI::Option* add_number(CLI::App& app, const std::string& flag, double& target, const std::string& help) {
    return app
        .add_option_function<std::string>(
            flag, [&target, flag](const std::string& text) { target = parse_number(flag, text); }, help)
        ->type_name("X");
}

inline std::vector<std::string> split_commas(const std::string& text) {
    std::vector<std::string> out;
    std::stringstream in(text);
    std::string part;
    while (std::getline(in, part, ',')) out.push_back(part);
    return out;
}

// --delimiter C: a CSV's field separator, one character, or "tab" (a tab is
// awkward to type in a shell).
inline CLI::Option* add_delimiter(CLI::App& app, char& target) {
    return app
        .add_option_function<std::string>(
            "--delimiter",
            [&target](const std::string& text) {
                if (text == "tab" || text == "\\t") target = '\t';
                else if (text.size() == 1 && text[0] != '\n' && text[0] != '\r') target = text[0];
                else throw Usage{"--delimiter: expected one character (',', ';') or 'tab', got '" + text + "'"};
            },
            "the tracks' field separator: one character, or tab (default ,)")
        ->type_name("C");
}

// --device D, as every command that opens a device takes it.
inline CLI::Option* add_device(CLI::App& app, std::string& target) {
    return app.add_option("--device", target, "device index or part of its name (swarmcl devices)")->type_name("D");
}

}  // namespace swarmcl_cli
