// Per-module line and toggle coverage from Verilator coverage.dat files.
//
//   rtl_coverage_report [--min-line P] [--waivers FILE] [--list-uncovered] a.dat [b.dat ...]
//
// Every point of every file is read (Verilator's format: one line per point,
// `C '<key>\2<value>\1<key>\2<value>...' <count>`); points of the same module,
// type, file, line, column and comment are merged over instances and over
// files (counts summed), so a line is covered if any instance in any test
// executed it; parameterisations of a module (Verilator's <module>__<suffix>)
// count as the module. The table gives, per module, the covered/total points of the
// line kind (v_line and v_branch: statement blocks and both sides of every
// if/case) and of the toggle kind (v_toggle: each bit of each signal seen
// both 0->1 and 1->0 counts as toggled once Verilator counts it).
//
// A waiver file lists uncovered line points that are explained rather than
// covered, one per line: `<file basename>:<line> <reason>` (# comments).
// Exit status: 0 when every module's line coverage, counting waived points as
// covered, is >= P (default 0) and no waiver is stale (names a covered or
// missing point); 1 otherwise; 2 on bad arguments or unreadable files.
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

namespace {

struct PointKey {
  std::string module;
  std::string kind;  // "line" or "toggle"
  std::string file;
  int line = 0;
  std::string column;
  std::string comment;
  auto tie() const { return std::tie(module, kind, file, line, column, comment); }
  bool operator<(const PointKey& o) const { return tie() < o.tie(); }
};

std::string basename(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

// Parses one `C '...' count` line into key/value pairs and the count.
bool parse_point(const std::string& text, std::map<std::string, std::string>& kv, uint64_t& count) {
  if (text.size() < 4 || text[0] != 'C' || text[2] != '\'') return false;
  const size_t close = text.rfind('\'');
  if (close == std::string::npos || close <= 2) return false;
  const std::string body = text.substr(3, close - 3);
  count = std::stoull(text.substr(close + 1));
  kv.clear();
  size_t pos = 0;
  while (pos < body.size()) {
    if (body[pos] == '\001') ++pos;
    const size_t sep = body.find('\002', pos);
    if (sep == std::string::npos) return false;
    size_t end = body.find('\001', sep + 1);
    if (end == std::string::npos) end = body.size();
    kv[body.substr(pos, sep - pos)] = body.substr(sep + 1, end - sep - 1);
    pos = end;
  }
  return true;
}

struct Waiver {
  std::string reason;
  bool used = false;
};

int usage() {
  std::cerr << "usage: rtl_coverage_report [--min-line P] [--waivers FILE] [--list-uncovered] "
               "coverage.dat...\n";
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  double min_line = 0.0;
  std::string waiver_path;
  bool list_uncovered = false;
  std::vector<std::string> inputs;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--min-line" && i + 1 < argc) {
      min_line = std::stod(argv[++i]);
    } else if (arg == "--waivers" && i + 1 < argc) {
      waiver_path = argv[++i];
    } else if (arg == "--list-uncovered") {
      list_uncovered = true;
    } else if (!arg.empty() && arg[0] == '-') {
      return usage();
    } else {
      inputs.push_back(arg);
    }
  }
  if (inputs.empty()) return usage();

  std::map<std::string, Waiver> waivers;  // "file:line" -> reason
  if (!waiver_path.empty()) {
    std::ifstream in(waiver_path);
    if (!in) {
      std::cerr << "rtl_coverage_report: cannot read waivers " << waiver_path << "\n";
      return 2;
    }
    std::string text;
    while (std::getline(in, text)) {
      if (text.empty() || text[0] == '#') continue;
      const size_t space = text.find(' ');
      if (space == std::string::npos || text.find(':') > space) {
        std::cerr << "rtl_coverage_report: bad waiver line: " << text << "\n";
        return 2;
      }
      waivers[text.substr(0, space)] = Waiver{text.substr(space + 1), false};
    }
  }

  std::map<PointKey, uint64_t> points;
  for (const std::string& path : inputs) {
    std::ifstream in(path);
    if (!in) {
      std::cerr << "rtl_coverage_report: cannot read " << path << "\n";
      return 2;
    }
    std::string text;
    std::map<std::string, std::string> kv;
    while (std::getline(in, text)) {
      if (text.empty() || text[0] == '#') continue;
      uint64_t count = 0;
      if (!parse_point(text, kv, count)) {
        std::cerr << "rtl_coverage_report: unparsable line in " << path << "\n";
        return 2;
      }
      const std::string page = kv["page"];  // v_line/<module>, v_toggle/<module>, ...
      const size_t slash = page.find('/');
      if (slash == std::string::npos) continue;
      const std::string type = page.substr(0, slash);
      PointKey key;
      // Verilator names a parameterisation <module>__<suffix>: one row per module.
      key.module = page.substr(slash + 1);
      if (const size_t variant = key.module.find("__"); variant != std::string::npos) {
        key.module.resize(variant);
      }
      if (type == "v_line" || type == "v_branch") {
        key.kind = "line";
      } else if (type == "v_toggle") {
        key.kind = "toggle";
      } else {
        continue;  // user assertions/cover properties are not in the table
      }
      key.file = basename(kv["f"]);
      key.line = std::stoi(kv["l"]);
      key.column = kv["n"];
      key.comment = kv["o"];
      points[key] += count;
    }
  }
  if (points.empty()) {
    std::cerr << "rtl_coverage_report: no coverage points in the input\n";
    return 2;
  }

  struct Tally {
    uint64_t line_total = 0, line_hit = 0, line_waived = 0, toggle_total = 0, toggle_hit = 0;
  };
  std::map<std::string, Tally> modules;
  std::vector<std::string> unexplained;
  std::set<std::string> uncovered_lines;  // file:line with an uncovered line point
  std::set<std::string> covered_lines;
  for (const auto& [key, count] : points) {
    Tally& t = modules[key.module];
    if (key.kind == "toggle") {
      ++t.toggle_total;
      t.toggle_hit += count > 0 ? 1 : 0;
      continue;
    }
    ++t.line_total;
    const std::string where = key.file + ":" + std::to_string(key.line);
    if (count > 0) {
      ++t.line_hit;
      covered_lines.insert(where);
      continue;
    }
    uncovered_lines.insert(where);
    if (auto w = waivers.find(where); w != waivers.end()) {
      w->second.used = true;
      ++t.line_waived;
      if (list_uncovered) {
        std::printf("  waived   %-28s %-10s %s  (%s)\n", where.c_str(), key.module.c_str(),
                    key.comment.c_str(), w->second.reason.c_str());
      }
    } else {
      unexplained.push_back(where + " " + key.module + " " + key.comment);
    }
  }

  auto pct = [](uint64_t hit, uint64_t total) {
    return total == 0 ? 100.0 : 100.0 * static_cast<double>(hit) / static_cast<double>(total);
  };
  std::printf("%-16s %16s %8s %10s %18s %8s\n", "module", "line points", "line %", "+waived %",
              "toggle points", "toggle %");
  bool ok = true;
  Tally all;
  for (const auto& [module, t] : modules) {
    const double line_pct = pct(t.line_hit, t.line_total);
    const double with_waivers = pct(t.line_hit + t.line_waived, t.line_total);
    std::printf("%-16s %7llu / %6llu %7.2f%% %9.2f%% %8llu / %7llu %7.2f%%\n", module.c_str(),
                static_cast<unsigned long long>(t.line_hit),
                static_cast<unsigned long long>(t.line_total), line_pct, with_waivers,
                static_cast<unsigned long long>(t.toggle_hit),
                static_cast<unsigned long long>(t.toggle_total), pct(t.toggle_hit, t.toggle_total));
    if (with_waivers < min_line) ok = false;
    all.line_total += t.line_total;
    all.line_hit += t.line_hit;
    all.line_waived += t.line_waived;
    all.toggle_total += t.toggle_total;
    all.toggle_hit += t.toggle_hit;
  }
  std::printf("%-16s %7llu / %6llu %7.2f%% %9.2f%% %8llu / %7llu %7.2f%%\n", "all",
              static_cast<unsigned long long>(all.line_hit),
              static_cast<unsigned long long>(all.line_total), pct(all.line_hit, all.line_total),
              pct(all.line_hit + all.line_waived, all.line_total),
              static_cast<unsigned long long>(all.toggle_hit),
              static_cast<unsigned long long>(all.toggle_total),
              pct(all.toggle_hit, all.toggle_total));

  if (!unexplained.empty()) {
    std::printf("uncovered line points without a waiver: %zu\n", unexplained.size());
    for (const std::string& u : unexplained) std::printf("  uncovered %s\n", u.c_str());
  }
  for (const auto& [where, w] : waivers) {
    if (!w.used) {
      std::printf("stale waiver (point covered or absent): %s %s\n", where.c_str(),
                  w.reason.c_str());
      ok = false;
    }
  }
  if (min_line > 0.0) {
    std::printf("line coverage bar %.1f%% per module (waived points counted): %s\n", min_line,
                ok ? "met" : "NOT met");
  }
  return ok ? 0 : 1;
}
