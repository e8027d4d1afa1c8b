// shadelab: lighting models as OpenCL kernels on PoCL, checked against double-precision references.
#include <iostream>

#include "app/commands.hpp"
#include "core/error.hpp"

int main(int argc, char** argv) {
    CLI::App app{"shadelab: classic lighting models as OpenCL kernels (PoCL), checked against references"};
    app.require_subcommand(1);
    app.set_help_all_flag("--help-all", "Show help for every command");
    shadelab::app::add_render_command(app);
    shadelab::app::add_models_command(app);
    shadelab::app::add_devices_command(app);
    shadelab::app::add_moon_command(app);
    shadelab::app::add_batch_command(app);
    shadelab::app::add_compare_command(app);
    shadelab::app::add_plan_command(app);
    shadelab::app::add_chart_command(app);
    shadelab::app::add_fit_command(app);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e);
    } catch (const shadelab::Error& e) {
        std::cerr << "shadelab: error: " << e.what() << "\n";
        return 1;
    } catch (const std::exception& e) {
        std::cerr << "shadelab: internal error: " << e.what() << " (please report this)\n";
        return 2;
    }
    return 0;
}
