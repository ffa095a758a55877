#include "browser_support.hpp"

#include <catch2/catch.hpp>

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>

#include "formats/atomic_file.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;

namespace sodaevo::test {

std::string hex_bits(double v) {
  std::uint64_t bits;
  std::memcpy(&bits, &v, sizeof v);
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(bits));
  return buf;
}

std::string find_chromium() {
  for (const char* name : {"chromium", "chromium-browser"}) {
    const auto r = run_shell(std::string("command -v ") + name);
    if (r.exit_code == 0 && !r.output.empty()) return r.output.substr(0, r.output.find('\n'));
  }
  return {};
}

std::string chromium_command(const std::string& chromium, const fs::path& profile) {
  return "timeout 90 " + chromium +
         " --headless --no-sandbox --disable-gpu --disable-background-networking --no-first-run"
         " --disable-extensions --disable-quic --disable-component-update --disable-sync"
         " --user-data-dir=" + profile.string() + " --enable-logging=stderr --v=0";
}

DumpedPage dump_dom(const std::string& chromium, const std::string& url, const fs::path& work,
                    const std::string& extra_flags) {
  static int runs = 0;
  ++runs;
  const fs::path profile = work / ("dump-profile" + std::to_string(runs));
  const fs::path dom = work / ("dump" + std::to_string(runs) + ".html"), log = work / ("dump" + std::to_string(runs) + ".log");
  const auto r = run_shell("( " + chromium_command(chromium, profile) + " " + extra_flags + " --dump-dom '" + url + "' > " +
                           dom.string() + " 2> " + log.string() + " )");
  INFO("chromium on " << url.substr(0, 300) << ":\n" << r.output);
  REQUIRE(r.exit_code == 0);
  DumpedPage p;
  p.dom = soda::read_whole_file(dom);
  std::ifstream in(log);
  for (std::string line; std::getline(in, line);) {
    if (line.find(":CONSOLE") != std::string::npos) p.console.push_back(line);
  }
  return p;
}

DumpedPage dump_dom_until(const std::string& chromium, const std::string& url, const fs::path& work,
                          const std::string& extra_flags, const std::function<bool(const std::string&)>& done,
                          int attempts) {
  DumpedPage page = dump_dom(chromium, url, work, extra_flags);
  for (int a = 1; a < attempts && !done(page.dom); ++a) page = dump_dom(chromium, url, work, extra_flags);
  return page;
}

std::string shell_quoted(const std::string& text) {
  std::string out = "'";
  for (char c : text) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

std::string wait_in_page(const std::string& chromium, const std::string& url, const std::string& condition,
                         const std::string& expression, const fs::path& work, int timeout_s, bool run_links) {
  static int runs = 0;
  const fs::path out = work / ("wait" + std::to_string(++runs) + ".json");
  const fs::path script = fs::path(SODAEVO_MODELS_DIR).parent_path() / "web" / "chromium_wait.js";
  const auto r = run_shell("node " + shell_quoted(script.string()) + (run_links ? " --run-links " : " ") +
                           shell_quoted(chromium) + " " + shell_quoted(url) + " " + shell_quoted(condition) + " " +
                           shell_quoted(expression) + " " + std::to_string(timeout_s) + " > " + shell_quoted(out.string()));
  INFO("chromium_wait.js on " << url.substr(0, 300) << ": " << r.output);
  REQUIRE(r.exit_code == 0);
  return soda::read_whole_file(out);
}

} // namespace sodaevo::test
