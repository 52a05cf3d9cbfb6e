// lightbake: one executable, one subcommand per job. Each subcommand is a thin layer over
// the libraries in bake/ and viewer/; its options bind the same params structs the viewer uses.

#include <CLI/CLI.hpp>
#ifdef __GLIBC__
#include <malloc.h>
#endif
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <exception>
#include <new>
#include <string>

#include "app/address_space.h"
#include "app/commands.h"
#include "bake/message_line.h"
#include "app/load.h"

namespace lb::app {
void fail(const std::string& message) {
  lb::print_message("error", message);
  throw ExitCode{1};
}
}  // namespace lb::app

namespace {

// What a command prints on stdout is its result: one that did not all arrive fails the run.
// Flushed here, where a message and the status can still say so (exit's own flush is silent).
int finish_stdout(int status) {
  errno = 0;
  const bool flushed = std::fflush(stdout) == 0;
  if (flushed && !std::ferror(stdout)) return status;
  const char* reason = !flushed && errno != 0 ? std::strerror(errno) : "write error";
  std::fprintf(stderr, "lightbake: error: stdout: cannot write the output: %s\n", reason);
  return status != 0 ? status : 1;
}

}  // namespace

int main(int argc, char** argv) {
  // A file-size limit (ulimit -f) or a closed pipe (| head) then fails the write with EFBIG or
  // EPIPE, which the writers report and clean up after, instead of killing the process
  // mid-write. Progress lines that cannot be written are dropped (nothing checks them).
  std::signal(SIGXFSZ, SIG_IGN);
  std::signal(SIGPIPE, SIG_IGN);
#ifdef __GLIBC__
  // Freed memory at the top of a heap goes back to the system past 4 MiB, in worker threads'
  // heaps too: glibc's default threshold grows with the largest block freed, and malloc_trim
  // (release_freed_memory) leaves a thread heap's top alone, so a bake's peak resident memory
  // hung on which thread freed what last (bench/light_groups.py's four groups: 337 or 384 MiB
  // in runs of the same bake; with it 335 MiB in each of 13).
  mallopt(M_TRIM_THRESHOLD, 4 << 20);
#endif

  CLI::App app{"lightbake: an interactive lightmap baker after Shirley's three-pass method"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "lightbake 0.1");

  lb::app::register_info(app);
  lb::app::register_bake(app);
  lb::app::register_render(app);
  lb::app::register_reference(app);
  lb::app::register_snapshot(app);
  lb::app::register_view(app);
  lb::app::register_compare(app);
  lb::app::register_export(app);
  lb::app::register_merge(app);
  lb::app::add_scene_load_flags(app);
  for (CLI::App* command : app.get_subcommands({})) lb::app::add_address_space_check(*command);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return finish_stdout(app.exit(e));
  } catch (const lb::app::ExitCode& code) {
    return finish_stdout(code.value);
  } catch (const std::bad_alloc&) {
    lb::print_message("error", lb::app::out_of_memory_text());
    return finish_stdout(1);
  } catch (const std::exception& e) {
    lb::print_message("error", e.what());
    return finish_stdout(1);
  }
  return finish_stdout(0);
}
