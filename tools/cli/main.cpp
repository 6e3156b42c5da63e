// SPDX-License-Identifier: Apache-2.0
// smoothforce: command line of the SmoothForce engine. Exit status: 0 success, 1 bad input,
// 2 usage, 3 a safety fault in `loop`, 130/143 interrupted by SIGINT/SIGTERM (cli_exit.h).
#include <cstdio>
#include <exception>
#include <iostream>
#include <new>

#include <smoothforce/base/error.h>
#include <smoothforce/config.h>
#include <smoothforce/version.h>

#include "cli_common.h"
#include "cli_exit.h"
#include "cmd_generate.h"
#include "cmd_loop.h"
#include "cmd_sweep.h"
#include "cmd_trace.h"

int main(int argc, char** argv) {
  using namespace sf::cli;
  installSignalHandlers();
  CLI::App app{"SmoothForce: smooth haptic force on coarse polygon meshes (n-sided Gregory patches)"};
  app.require_subcommand(1);
  app.set_version_flag("--version", SF_HAS_OPENCL ? "smoothforce " SF_VERSION_STRING
                                                  : "smoothforce " SF_VERSION_STRING
                                                    " (CPU-only: built without OpenCL)");
  app.footer(
      "Exit status: 0 success, 1 bad input (a file or its values), 2 usage (the command line), 3 a safety fault "
      "in loop, 130/143 interrupted by SIGINT/SIGTERM. Results go to stdout or files, diagnostics to stderr.");
  addCacheCommands(app);
  addEvalCommand(app);
  addExportCommand(app);
  addTraceCommand(app);
  addLoopCommand(app);
  addSweepCommands(app);
  addGenerateCommand(app);
  auto usage = [](const std::exception& e) {  // one line, exit 2
    std::fprintf(stderr, "smoothforce: %s (see --help)\n", e.what());
    return kExitUsage;
  };
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    return usage(e);
  } catch (const UsageError& e) {
    return usage(e);
  } catch (const sf::OptionError& e) {  // an option value the mesh, scene or files make impossible
    return usage(e);
  } catch (const Interrupted& e) {
    std::fprintf(stderr, "smoothforce: %s\n", e.what());
    return 128 + e.signal();
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "smoothforce: out of memory\n");
    return kExitInput;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "smoothforce: %s\n", e.what());
    return kExitInput;
  }
  // a report or JSON summary on stdout that did not all arrive (a full disk, /dev/full) is a failed
  // write, as `-o -` reports it; after an error already reported, that one line stands
  const int status = exitStatus();
  std::cout.flush();
  if (status == 0 && (!std::cout || std::fflush(stdout) != 0 || std::ferror(stdout))) {
    std::fprintf(stderr, "smoothforce: <stdout>: write failed\n");
    return kExitInput;
  }
  return status;
}
