// The swarmcl program's commands.  Each adds its subcommand to the program
// (its options and --help text, CLI11) and returns what runs it once the
// command line is parsed: the exit status, or Usage / Failure thrown
// (cli_support.hpp).  A new command is one file with its add_<name>() and
// one line in main.cpp (docs/architecture.md, "Where a change goes").
#pragma once
#include <functional>

namespace CLI {
class App;
}

namespace swarmcl_cli {

struct Command {
    CLI::App* app = nullptr;
    std::function<int()> run;
    std::function<void()> more_help;  // printed after the command's --help (fit: Python's options)
};

Command add_run(CLI::App& program);       // run.cpp
Command add_resume(CLI::App& program);    // run.cpp
Command add_evaluate(CLI::App& program);  // evaluate.cpp
Command add_fit(CLI::App& program);       // fit.cpp
Command add_sweep(CLI::App& program);     // fit.cpp
Command add_devices(CLI::App& program);   // devices.cpp
Command add_validate(CLI::App& program);  // validate.cpp

}  // namespace swarmcl_cli
