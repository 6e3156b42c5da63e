// smoothforce: command line of the SmoothForce engine.
#include <cstdio>
#include <exception>
#include <new>

#include <smoothforce/config.h>
#include <smoothforce/version.h>

#include "cli_common.h"
#include "cmd_generate.h"
#include "cmd_loop.h"
#include "cmd_sweep.h"
#include "cmd_trace.h"

int main(int argc, char** argv) {
  CLI::App app{"SmoothForce: smooth haptic force on coarse polygon meshes (n-sided Gregory patches)"};
  app.require_subcommand(1);
  app.set_version_flag("--version", SF_HAS_OPENCL ? "smoothforce " SF_VERSION_STRING
                                                  : "smoothforce " SF_VERSION_STRING
                                                    " (CPU-only: built without OpenCL)");
  sf::cli::addCacheCommands(app);
  sf::cli::addEvalCommand(app);
  sf::cli::addExportCommand(app);
  sf::cli::addTraceCommand(app);
  sf::cli::addLoopCommand(app);
  sf::cli::addSweepCommands(app);
  sf::cli::addGenerateCommand(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "smoothforce: %s (see --help)\n", e.what());
    return e.get_exit_code() ? e.get_exit_code() : 2;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "smoothforce: out of memory\n");
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "smoothforce: %s\n", e.what());
    return 1;
  }
  return 0;
}
