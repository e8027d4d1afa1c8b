// shadelab: lighting models as OpenCL kernels on PoCL, checked against double-precision references.
//
// Exit codes, for every command: 0 success; 1 bad input or a failed job (shadelab::Error, one line); 2 a usage
// error (unknown subcommand, flag or model name on the command line, a missing or malformed argument), with a
// "did you mean" hint where one is close. Never a signal, never an unhandled exception.
#include <iostream>
#include <string>
#include <vector>

#include "app/commands.hpp"
#include "core/error.hpp"
#include "core/log.hpp"
#include "core/text.hpp"

#ifndef SHADELAB_VERSION
#define SHADELAB_VERSION "0.0.0"
#endif

namespace {

constexpr int kExitBadInput = 1;
constexpr int kExitUsage = 2;

std::vector<std::string> subcommand_names(const CLI::App& app) {
    std::vector<std::string> names;
    for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; })) names.push_back(sub->get_name());
    return names;
}

// Every long and short flag name of a (sub)command, with its dashes: the candidates for a mistyped flag.
std::vector<std::string> flag_names(const CLI::App& app) {
    std::vector<std::string> names;
    for (const CLI::Option* o : app.get_options()) {
        for (const auto& l : o->get_lnames()) names.push_back("--" + l);
        for (const auto& s : o->get_snames()) names.push_back("-" + s);
    }
    return names;
}

// The deepest subcommand the user reached (what a mistyped flag belongs to).
const CLI::App* reached(const CLI::App& app) {
    for (const CLI::App* sub : app.get_subcommands())
        if (sub->parsed()) return reached(*sub);
    return &app;
}

std::string command_path(const CLI::App* a) {
    std::string path;
    for (; a != nullptr && a->get_parent() != nullptr; a = a->get_parent()) path = a->get_name() + (path.empty() ? "" : " " + path);
    return path;
}

// A usage error as one line (plus the hint where to read more), exit 2.
int usage_error(const CLI::App& app, const CLI::ParseError& e, int argc, char** argv) {
    std::string msg = e.what();
    const CLI::App* at = reached(app);
    // An unknown first word: CLI11 says only that a subcommand is required or that the word was not expected.
    if (at == &app && argc > 1 && argv[1][0] != '-') {
        const std::string word = argv[1];
        msg = "unknown command '" + word + "'" + shadelab::did_you_mean(word, subcommand_names(app)) +
              "; commands: ";
        std::string list;
        for (const auto& n : subcommand_names(app)) list += (list.empty() ? "" : ", ") + n;
        msg += list;
    } else if (dynamic_cast<const CLI::ExtrasError*>(&e) != nullptr) {
        // "The following arguments were not expected: --sise 512": name the closest flag of that command.
        std::vector<std::string> extras = at->remaining();   // with fallthrough, the top level holds them
        for (const auto& x : app.remaining()) extras.push_back(x);
        for (const auto& extra : extras) {
            if (extra.size() < 2 || extra[0] != '-') continue;
            const std::string flag = extra.substr(0, extra.find('='));
            msg = "unknown option '" + flag + "'" + (at == &app ? "" : " for '" + command_path(at) + "'") +
                  shadelab::did_you_mean(flag, flag_names(*at));
            break;
        }
    }
    std::cerr << "shadelab: error: " << msg << " (see 'shadelab " << command_path(at) << (at == &app ? "" : " ")
              << "--help')\n";
    return kExitUsage;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"shadelab: classic lighting models as OpenCL kernels (PoCL), checked against references"};
    app.require_subcommand(1);
    app.set_help_all_flag("--help-all", "Show help for every command");
    app.fallthrough();   // global flags (-q, -v) also after the subcommand: unknown there, they fall to here
    app.set_version_flag("--version", std::string("shadelab ") + SHADELAB_VERSION);
    // Global verbosity: results go to stdout, logs and progress to stderr; -q silences the logs, -v adds detail.
    auto* quiet = app.add_flag("-q,--quiet", "Only results and errors (no progress or logs on stderr)");
    auto* verbose = app.add_flag("-v,--verbose", "More detail on stderr")->excludes(quiet);
    app.parse_complete_callback([quiet, verbose] {
        shadelab::set_log_level(quiet->count() > 0 ? shadelab::LogLevel::Quiet
                                : verbose->count() > 0 ? shadelab::LogLevel::Verbose
                                                      : shadelab::LogLevel::Normal);
    });
    shadelab::app::add_render_command(app);
    shadelab::app::add_models_command(app);
    shadelab::app::add_devices_command(app);
    shadelab::app::add_moon_command(app);
    shadelab::app::add_batch_command(app);
    shadelab::app::add_compare_command(app);
    shadelab::app::add_plan_command(app);
    shadelab::app::add_chart_command(app);
    shadelab::app::add_view_command(app);
    shadelab::app::add_photometry_command(app);
    shadelab::app::add_fit_command(app);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        if (e.get_exit_code() == 0) return app.exit(e);   // --help, --version
        return usage_error(app, e, argc, argv);
    } catch (const shadelab::UsageError& e) {
        std::cerr << "shadelab: error: " << e.what() << "\n";
        return kExitUsage;
    } catch (const shadelab::Error& e) {
        std::cerr << "shadelab: error: " << e.what() << "\n";
        return kExitBadInput;
    } catch (const std::exception& e) {
        std::cerr << "shadelab: internal error: " << e.what() << " (please report this)\n";
        return kExitBadInput;
    }
    return 0;
}
