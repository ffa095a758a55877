// Headless Chromium for the browser tests (Debian's `chromium`, installed by
// ./build.sh test): finding it, the command line, and a page's DOM and console
// after it ran.
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace sodaevo::test {

/// A double's 64 bits as 16 lowercase hex digits: how the pages report numbers
/// (web/engine_api.cpp's state bits, Evolve mode's data-fitness-bits).
std::string hex_bits(double v);

/// The path of `chromium` or `chromium-browser` on PATH; empty if neither.
std::string find_chromium();

/// A headless Chromium command (no sandbox, no GPU, no network side traffic, its
/// own profile folder, the console on stderr), up to a URL or further flags.
std::string chromium_command(const std::string& chromium, const std::filesystem::path& profile);

struct DumpedPage {
  std::string dom;
  std::vector<std::string> console; ///< CONSOLE lines of Chromium's log
};

/// Opens `url` with `extra_flags` in a fresh profile under `work` and dumps its
/// DOM (--dump-dom); fails the test if Chromium fails.
DumpedPage dump_dom(const std::string& chromium, const std::string& url, const std::filesystem::path& work,
                    const std::string& extra_flags = "");

/// dump_dom again (up to `attempts` times in all) while `done(dom)` is false.
/// Why: --virtual-time-budget does not wait for work outside Chromium's scheduler
/// (compiling the WebAssembly engine, a DecompressionStream), so on a busy machine
/// the DOM can be dumped before the page is done; a page that never gets done
/// still fails the test's own checks after the last attempt.
DumpedPage dump_dom_until(const std::string& chromium, const std::string& url, const std::filesystem::path& work,
                          const std::string& extra_flags, const std::function<bool(const std::string&)>& done,
                          int attempts = 3);

/// `text` quoted for the shell ('...').
std::string shell_quoted(const std::string& text);

/// web/chromium_wait.js: opens `url` in headless Chromium in real time (no virtual
/// time: Web Workers and the page's clock run as a user's), waits up to `timeout_s`
/// for the JavaScript `condition`, and returns `expression`'s JSON text; fails the
/// test on a timeout. `run_links`: an "#evolve=...&run" link runs at once.
std::string wait_in_page(const std::string& chromium, const std::string& url, const std::string& condition,
                         const std::string& expression, const std::filesystem::path& work, int timeout_s = 240,
                         bool run_links = false);

} // namespace sodaevo::test
