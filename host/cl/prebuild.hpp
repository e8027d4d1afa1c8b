// Building several OpenCL programs at once (issue 13 item 6: the first cold run). PoCL compiles a program in
// clBuildProgram on the calling thread (front end, then linking its kernel library) and compiles each kernel at
// its first launch; Runtime::build builds different programs on different threads concurrently (a program asked
// for while another thread builds it waits for that build), so a caller that knows which programs it will need
// builds them all ahead here, on every core, instead of one after another at first use.
#pragma once
#include <string>
#include <vector>

#include "cl/runtime.hpp"

namespace shadelab {

// One program Runtime::build would make: its main file, defines and extra options.
struct ProgramRequest {
    std::string main_file;
    std::vector<std::string> defines;
    std::string extra_options;
};

// Builds every request not built yet on up to `threads` threads (0: the hardware's); the first failure is
// rethrown once every thread has finished.
void prebuild(Runtime& runtime, const std::vector<ProgramRequest>& requests, unsigned threads = 0);

}  // namespace shadelab
