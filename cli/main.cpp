// The swarmcl command line: run a scenario file, resume a run, evaluate or
// fit a scenario against tracks, list devices, validate a scenario.  It
// uses only the public C API, like any other program would.  The command
// line is parsed by CLI11; each command is one file (commands.hpp).
//
//   swarmcl run SCENARIO.json [--steps N] [--out DIR] [--format csv,npy,vtp] ...   (run.cpp)
//   swarmcl resume DIR [--device D] [--quiet]                                     (run.cpp)
//   swarmcl evaluate SCENARIO.json --tracks FILE.csv [...]                         (evaluate.cpp)
//   swarmcl fit SCENARIO.json --tracks FILE.csv --ranges RANGES.json [...]         (fit.cpp)
//   swarmcl devices                                                                (devices.cpp)
//   swarmcl validate SCENARIO.json                                                 (validate.cpp)
//   swarmcl [COMMAND] --help, swarmcl help [COMMAND], swarmcl --version
//
// Exit status: 0 done, 1 failed (the message on stderr), 2 usage error (the
// message and the command's usage on stderr).
#include <cstdio>
#include <exception>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <swarmcl/swarmcl.h>

#include "cli_support.hpp"
#include "commands.hpp"

using namespace swarmcl_cli;

namespace {

// "swarmcl 0.2.0 (library 0.2.0)": the version built against and the one loaded.
std::string version_text() {
    return "swarmcl " + std::to_string(SWCL_VERSION_MAJOR) + "." + std::to_string(SWCL_VERSION_MINOR) + "." +
           std::to_string(SWCL_VERSION_PATCH) + " (library " + swcl_version_string() + ")";
}

// The command being parsed when an error came, or nullptr.
const Command* selected(const std::vector<Command>& commands) {
    for (const Command& c : commands)
        if (c.app->parsed()) return &c;
    return nullptr;
}

// A usage error: the message, then the command's usage line and where its
// options are (or the whole help when no command was chosen), on stderr.
int usage_error(const CLI::App& program, const CLI::Formatter& format, const Command* command,
                const std::string& message) {
    std::fprintf(stderr, "swarmcl: %s\n", message.c_str());
    if (command) {
        const std::string name = command->app->get_name();
        std::fprintf(stderr, "%s'swarmcl %s --help' lists its options\n",
                     format.make_usage(command->app, "swarmcl " + name).c_str(), name.c_str());
    } else {
        std::fputs(format.make_help(&program, "swarmcl", CLI::AppFormatMode::Normal).c_str(), stderr);
    }
    return 2;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App program("swarmcl: swarms of flying insects on OpenCL devices", "swarmcl");
    const auto format = std::make_shared<CLI::Formatter>();
    format->label("Usage", "usage");
    format->column_width(30);
    program.formatter(format);
    program.set_version_flag("--version", version_text(), "print the version of swarmcl and of the library, and exit");
    program.require_subcommand(1);
    // An option given twice takes its last value, as before CLI11 (the commands inherit it).
    program.option_defaults()->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
    program.footer("'swarmcl COMMAND --help' lists a command's options (docs/scenarios.md, docs/evaluation.md).");

    std::vector<Command> commands = {add_run(program),     add_resume(program), add_evaluate(program),
                                     add_fit(program),     add_sweep(program),   add_devices(program), add_validate(program)};
    // `swarmcl help [COMMAND]`: the same as `swarmcl [COMMAND] --help`.
    CLI::App* help = program.add_subcommand("help", "Show the help of swarmcl or of one command");
    std::string help_topic;
    help->add_option("COMMAND", help_topic, "the command")->type_name("");

    if (argc < 2) return usage_error(program, *format, nullptr, "no command given");
    const std::string first = argv[1];
    if (!first.empty() && first[0] != '-' &&
        program.get_subcommands([&first](CLI::App* c) { return c->check_name(first); }).empty())
        return usage_error(program, *format, nullptr, "unknown command '" + first + "'");

    try {
        program.parse(argc, argv);
        if (help->parsed()) {
            if (help_topic.empty()) {
                std::fputs(format->make_help(&program, "swarmcl", CLI::AppFormatMode::Normal).c_str(), stdout);
                return 0;
            }
            for (const Command& c : commands)
                if (c.app->get_name() == help_topic) {
                    std::fputs(c.app->help("swarmcl").c_str(), stdout);
                    if (c.more_help) c.more_help();
                    return 0;
                }
            return usage_error(program, *format, nullptr, "help: unknown command '" + help_topic + "'");
        }
        const Command* command = selected(commands);
        if (!command) return usage_error(program, *format, nullptr, "no command given");
        return command->run();
    } catch (const CLI::CallForHelp&) {
        const Command* command = selected(commands);
        std::fputs(program.help().c_str(), stdout);
        if (command && command->more_help) command->more_help();
        return 0;
    } catch (const CLI::CallForAllHelp&) {
        std::fputs(program.help("", CLI::AppFormatMode::All).c_str(), stdout);
        return 0;
    } catch (const CLI::CallForVersion& v) {
        std::printf("%s\n", v.what());
        return 0;
    } catch (const CLI::ParseError& e) {
        return usage_error(program, *format, selected(commands), e.what());
    } catch (const Usage& u) {
        return usage_error(program, *format, selected(commands), u.message);
    } catch (const Failure& f) {
        std::fprintf(stderr, "swarmcl: %s\n", f.message.c_str());
        return 1;
    } catch (const std::exception& e) {  // a bug, never a crash
        std::fprintf(stderr, "swarmcl: internal error: %s\n", e.what());
        return 1;
    }
}
