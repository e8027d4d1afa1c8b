#include <iomanip>
#include <iostream>

#include "app/commands.hpp"
#include "cl/runtime.hpp"
#include "models/catalogue.hpp"

namespace shadelab::app {

void add_models_command(CLI::App& app) {
    auto* cmd = app.add_subcommand("models", "List every lighting model with its parameters and ranges");
    cmd->callback([] {
        for (const auto& m : model_catalogue()) {
            std::cout << std::left << std::setw(32) << m.name << m.summary << "\n";
            for (const auto& p : m.params)
                std::cout << "    " << std::setw(14) << p.name << "default " << p.def << ", range [" << p.lo << ", "
                          << p.hi << "]  " << p.doc << "\n";
        }
    });
}

void add_devices_command(CLI::App& app) {
    auto* cmd = app.add_subcommand("devices", "Show the OpenCL device shadelab picks and where its kernels are");
    cmd->callback([] {
        Runtime rt;
        std::cout << "device:  " << rt.device_description() << "\n"
                  << "kernels: " << rt.kernel_dir() << "\n"
                  << "choose another with SHADELAB_CL_PLATFORM=<name part> and SHADELAB_CL_DEVICE=<index>\n";
    });
}

}  // namespace shadelab::app
