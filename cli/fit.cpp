// `swarmcl fit` and `swarmcl sweep`: parameter estimation and sweeps run in
// the Python package.  Fit: parameter estimation runs in the Python package (CMA-ES and
// the GA come from cma and DEAP, the ranks from mpi4py), so this command
// hands its arguments to `python -m swarmcl fit`, in place: under
// `mpirun -np R swarmcl fit ...` each rank becomes that Python process.
// Its options are the Python program's (bindings/python/swarmcl/fitting.py),
// declared there once: `swarmcl fit --help` prints this command's help and
// then theirs.
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <spawn.h>
#include <string>
#include <sys/wait.h>
#include <unistd.h>
#include <vector>

#include <CLI/CLI.hpp>

#include "cli_support.hpp"
#include "commands.hpp"

namespace swarmcl_cli {
namespace {

std::string python_program() {
    const char* env = std::getenv("SWARMCL_PYTHON");
    return env && *env ? env : "python3";
}

std::vector<char*> raw_args(std::vector<std::string>& args) {
    std::vector<char*> raw;
    for (auto& a : args) raw.push_back(a.data());
    raw.push_back(nullptr);
    return raw;
}

// A command that runs `python -m swarmcl NAME` with its arguments, in place.
Command python_command(CLI::App& program, const std::string& name, const std::string& description,
                       const std::string& footer) {
    CLI::App* app = program.add_subcommand(name, description);
    // Everything after the command's name goes to Python as it is.
    app->prefix_command();
    app->allow_extras();
    app->footer(footer);
    Command command;
    command.app = app;
    command.more_help = [name] {
        // The Python program's own --help: its options are declared there.
        const std::string python = python_program();
        std::vector<std::string> args = {python, "-m", "swarmcl", name, "--help"};
        std::vector<char*> raw = raw_args(args);
        std::fflush(stdout);
        pid_t pid = 0;
        int status = -1;
        if (posix_spawnp(&pid, python.c_str(), nullptr, nullptr, raw.data(), environ) == 0)
            waitpid(pid, &status, 0);
        if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
            std::printf("\n(the options could not be listed: '%s -m swarmcl %s --help' failed; "
                        "pip install 'swarmcl[fit]' and set SWARMCL_PYTHON to that interpreter)\n",
                        python.c_str(), name.c_str());
    };
    command.run = [app, name]() -> int {
        const std::string python = python_program();
        std::vector<std::string> args = {python, "-m", "swarmcl", name};
        for (const std::string& a : app->remaining()) args.push_back(a);
        std::vector<char*> raw = raw_args(args);
        std::fflush(stdout);
        execvp(python.c_str(), raw.data());
        throw Failure{name + " runs in the Python package: cannot start '" + python + "' (" + std::strerror(errno) +
                      "); pip install 'swarmcl[fit]' and set SWARMCL_PYTHON to that interpreter"};
    };
    return command;
}

}  // namespace

Command add_fit(CLI::App& program) {
    return python_command(
        program, "fit", "Fit a scenario's parameters to real tracks (CMA-ES or a GA; runs in the Python package)",
        "swarmcl fit SCENARIO.json --tracks FILE.csv --ranges RANGES.json [--method cmaes|ga]\n"
        "            [--generations G] [--population P] [--seed S] [...]\n"
        "runs $SWARMCL_PYTHON -m swarmcl fit with the same arguments (python3 by default;\n"
        "pip install 'swarmcl[fit]'), so under mpirun each rank is one Python process\n"
        "(docs/evaluation.md).  Its options, from Python:");
}

Command add_sweep(CLI::App& program) {
    return python_command(
        program, "sweep",
        "Run a grid or list of parameter values as the worlds of one swarm, a row per world (runs in the Python "
        "package)",
        "swarmcl sweep SCENARIO.json --grid GRID.json [--tracks FILE.csv] [--out sweep.json|sweep.csv] [...]\n"
        "runs $SWARMCL_PYTHON -m swarmcl sweep with the same arguments (python3 by default), so\n"
        "under mpirun each rank is one Python process running its share of the rows\n"
        "(docs/evaluation.md, \"Sweeps\").  Its options, from Python:");
}

}  // namespace swarmcl_cli
