// `swarmcl fit`: parameter estimation runs in the Python package (CMA-ES and
// the GA come from cma and DEAP, the ranks from mpi4py), so this command
// hands its arguments to `python -m swarmcl fit`, in place: under
// `mpirun -np R swarmcl fit ...` each rank becomes that Python process.
#include "fit.hpp"

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <string>
#include <unistd.h>
#include <vector>

#include "cli_support.hpp"

namespace swarmcl_cli {

int cmd_fit(int argc, char** argv) {
    const char* env = std::getenv("SWARMCL_PYTHON");
    const std::string python = env && *env ? env : "python3";
    std::vector<std::string> args = {python, "-m", "swarmcl", "fit"};
    for (int i = 0; i < argc; ++i) args.emplace_back(argv[i]);
    std::vector<char*> raw;
    for (auto& a : args) raw.push_back(a.data());
    raw.push_back(nullptr);
    std::fflush(stdout);
    execvp(python.c_str(), raw.data());
    throw Failure{"fit runs in the Python package: cannot start '" + python + "' (" + std::strerror(errno) +
                  "); pip install 'swarmcl[fit]' and set SWARMCL_PYTHON to that interpreter"};
}

}  // namespace swarmcl_cli
