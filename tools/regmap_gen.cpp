// regmap_gen: rtl_model/regmap.json -> the SystemVerilog package and include
// file, the C++ header and the Markdown register table. The JSON is the only
// place where a register address, field position or reset value is written.
//
// Usage: regmap_gen <regmap.json> <output dir>
// Writes <out>/ceilnav_reg_pkg.sv, <out>/ceilnav_regs.svh,
// <out>/ceilnav/regs.hpp, the C header <out>/ceilnav/ceilnav_regs.h and
// <out>/registers.md. Exits 1 with a message on any
// inconsistency (overlap, misalignment, field outside 32 bits, reset value
// wider than its field, unknown access type or side effect).
#include <algorithm>
#include <cctype>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace {

using nlohmann::json;

struct Field {
  std::string name;
  uint32_t lsb = 0;
  uint32_t width = 1;
  std::string access;  // ro, rw, wo, w1c
  uint32_t reset = 0;
  std::string param;  // reset value taken from this parameter (documentation)
  std::string desc;

  uint32_t mask() const {
    const uint32_t ones = width >= 32 ? 0xFFFFFFFFu : ((1u << width) - 1u);
    return ones << lsb;
  }
};

struct Register {
  std::string name;
  uint32_t offset = 0;
  uint32_t count = 1;  // > 1: an array of identical registers at offset + i * stride
  uint32_t stride = 4;
  std::string desc;
  std::string block;  // optional block the register belongs to ("" = always present)
  std::string read_effect = "none";
  std::string write_effect = "none";
  std::vector<Field> fields;

  uint32_t element_offset(uint32_t i) const { return offset + i * stride; }
  uint32_t reset() const {
    uint32_t v = 0;
    for (const Field& f : fields) v |= f.reset << f.lsb;
    return v;
  }
  uint32_t mask_of(const std::string& access) const {
    uint32_t m = 0;
    for (const Field& f : fields) {
      if (f.access == access) m |= f.mask();
    }
    return m;
  }
  std::string access_summary() const {
    std::vector<std::string> kinds;
    for (const Field& f : fields) {
      if (std::find(kinds.begin(), kinds.end(), f.access) == kinds.end()) kinds.push_back(f.access);
    }
    std::string s;
    for (const std::string& k : kinds) s += (s.empty() ? "" : "/") + k;
    return s;
  }
};

struct Param {
  std::string name;
  uint32_t value = 0;
  std::string desc;
};

// A build-time configuration of the device: which optional blocks it has.
struct Config {
  std::string name;
  std::vector<std::string> blocks;
  bool has(const std::string& block) const {
    return std::find(blocks.begin(), blocks.end(), block) != blocks.end();
  }
};

struct RegMap {
  std::string name;
  std::string desc;
  uint32_t addr_width = 0;
  std::vector<Param> params;
  std::vector<std::string> optional_blocks;  // blocks a configuration may leave out
  std::vector<Config> configs;
  std::vector<Register> registers;
};

[[noreturn]] void fail(const std::string& msg) {
  throw std::runtime_error(msg);
}

uint32_t parse_u32(const json& j, const std::string& what) {
  if (j.is_number_unsigned()) {
    const uint64_t v = j.get<uint64_t>();
    if (v > 0xFFFFFFFFull) fail(what + ": value does not fit 32 bits");
    return static_cast<uint32_t>(v);
  }
  if (!j.is_string()) fail(what + ": expected a number or a string");
  const std::string s = j.get<std::string>();
  size_t used = 0;
  unsigned long long v = 0;
  try {
    v = std::stoull(s, &used, 0);
  } catch (const std::exception&) {
    fail(what + ": not a number: " + s);
  }
  if (used != s.size() || v > 0xFFFFFFFFull) fail(what + ": bad value " + s);
  return static_cast<uint32_t>(v);
}

std::string upper(std::string s) {
  for (char& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return s;
}
std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}
// FRAME_DONE -> FrameDone
std::string camel(const std::string& s) {
  std::string out;
  bool up = true;
  for (char c : s) {
    if (c == '_') {
      up = true;
      continue;
    }
    out += up ? static_cast<char>(std::toupper(static_cast<unsigned char>(c)))
              : static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    up = false;
  }
  return out;
}
bool valid_name(const std::string& s) {
  if (s.empty() || !std::isupper(static_cast<unsigned char>(s[0]))) return false;
  return std::all_of(s.begin(), s.end(), [](char c) {
    return std::isupper(static_cast<unsigned char>(c)) ||
           std::isdigit(static_cast<unsigned char>(c)) || c == '_';
  });
}

std::string hex(uint32_t v, int digits) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "%0*X", digits, v);
  return buf;
}

RegMap parse(const json& j) {
  RegMap m;
  m.name = j.at("name").get<std::string>();
  m.desc = j.value("desc", "");
  m.addr_width = parse_u32(j.at("addr_width"), "addr_width");
  if (m.addr_width < 3 || m.addr_width > 32) fail("addr_width must be 3..32");
  if (parse_u32(j.at("data_width"), "data_width") != 32) fail("data_width must be 32");
  for (const json& p : j.value("params", json::array())) {
    m.params.push_back({p.at("name").get<std::string>(), parse_u32(p.at("value"), "param value"),
                        p.value("desc", "")});
  }
  for (const json& b : j.value("optional_blocks", json::array())) {
    const std::string name = b.get<std::string>();
    if (name.empty() || !std::islower(static_cast<unsigned char>(name[0]))) {
      fail("bad optional block name " + name);
    }
    m.optional_blocks.push_back(name);
  }
  for (const json& c : j.value("configurations", json::array())) {
    Config cfg{c.at("name").get<std::string>(), {}};
    for (const json& b : c.at("blocks")) {
      const std::string name = b.get<std::string>();
      if (std::find(m.optional_blocks.begin(), m.optional_blocks.end(), name) ==
          m.optional_blocks.end()) {
        fail("configuration " + cfg.name + ": unknown optional block " + name);
      }
      cfg.blocks.push_back(name);
    }
    m.configs.push_back(cfg);
  }
  if (!m.optional_blocks.empty() && m.configs.empty()) fail("optional blocks but no configuration");
  for (const json& r : j.at("registers")) {
    Register reg;
    reg.name = r.at("name").get<std::string>();
    if (!valid_name(reg.name)) fail("bad register name " + reg.name);
    const std::string where = "register " + reg.name;
    reg.offset = parse_u32(r.at("offset"), where + " offset");
    reg.count = r.contains("count") ? parse_u32(r.at("count"), where + " count") : 1u;
    reg.stride = r.contains("stride") ? parse_u32(r.at("stride"), where + " stride") : 4u;
    if (reg.count < 1 || reg.stride < 4 || reg.stride % 4 != 0) fail(where + ": bad count/stride");
    reg.desc = r.value("desc", "");
    reg.block = r.value("block", "");
    if (!reg.block.empty() && std::find(m.optional_blocks.begin(), m.optional_blocks.end(),
                                        reg.block) == m.optional_blocks.end()) {
      fail(where + ": unknown optional block " + reg.block);
    }
    reg.read_effect = r.value("read_effect", "none");
    reg.write_effect = r.value("write_effect", "none");
    for (const std::string& e : {reg.read_effect, reg.write_effect}) {
      if (e != "none" && e != "lut_index_inc" && e != "hist_index_inc" && e != "run_pop") {
        fail(where + ": unknown side effect " + e);
      }
    }
    uint32_t used = 0;
    for (const json& fj : r.at("fields")) {
      Field f;
      f.name = fj.at("name").get<std::string>();
      if (!valid_name(f.name)) fail(where + ": bad field name " + f.name);
      const std::string fwhere = where + "." + f.name;
      const std::string bits = fj.at("bits").get<std::string>();
      const size_t colon = bits.find(':');
      uint32_t msb = 0;
      if (colon == std::string::npos) {
        msb = f.lsb = parse_u32(json(bits), fwhere + " bits");
      } else {
        msb = parse_u32(json(bits.substr(0, colon)), fwhere + " msb");
        f.lsb = parse_u32(json(bits.substr(colon + 1)), fwhere + " lsb");
      }
      if (msb < f.lsb || msb > 31) fail(fwhere + ": bad bit range " + bits);
      f.width = msb - f.lsb + 1;
      f.access = fj.at("access").get<std::string>();
      if (f.access != "ro" && f.access != "rw" && f.access != "wo" && f.access != "w1c") {
        fail(fwhere + ": unknown access " + f.access);
      }
      f.reset = parse_u32(fj.at("reset"), fwhere + " reset");
      if ((f.reset << f.lsb) >> f.lsb != f.reset || ((f.reset << f.lsb) & ~f.mask()) != 0) {
        fail(fwhere + ": reset value wider than the field");
      }
      f.param = fj.value("param", "");
      if (!f.param.empty()) {
        const auto it = std::find_if(m.params.begin(), m.params.end(),
                                     [&](const Param& p) { return p.name == f.param; });
        if (it == m.params.end()) fail(fwhere + ": unknown parameter " + f.param);
        if (it->value != f.reset) fail(fwhere + ": reset differs from parameter " + f.param);
      }
      f.desc = fj.value("desc", "");
      if ((used & f.mask()) != 0) fail(fwhere + ": overlaps another field");
      used |= f.mask();
      reg.fields.push_back(f);
    }
    if (reg.fields.empty()) fail(where + ": no fields");
    m.registers.push_back(reg);
  }
  // Addresses: aligned, inside the window, no two registers on one word.
  std::map<uint32_t, std::string> taken;
  for (const Register& r : m.registers) {
    for (uint32_t i = 0; i < r.count; ++i) {
      const uint32_t a = r.element_offset(i);
      if (a % 4 != 0) fail(r.name + ": offset not word aligned");
      if (m.addr_width < 32 && a >= (1u << m.addr_width)) fail(r.name + ": offset outside window");
      if (!taken.emplace(a, r.name).second) {
        fail(r.name + ": offset 0x" + hex(a, 3) + " already used by " + taken[a]);
      }
    }
  }
  return m;
}

// ---- SystemVerilog: the same localparams as a package and as an include file.
std::string sv_body(const RegMap& m, const std::string& indent) {
  const std::string p = upper(m.name) + "_";
  const std::string aw = std::to_string(m.addr_width);
  std::ostringstream o;
  // A module uses a few of these; the rest must not trip verilator -Wall.
  o << indent << "// verilator lint_off UNUSEDPARAM\n";
  o << indent << "localparam int unsigned " << camel(m.name) << "AddrWidth = " << m.addr_width
    << ";\n";
  for (const Param& prm : m.params) {
    o << indent << "localparam int unsigned " << prm.name << " = " << prm.value << ";\n";
  }
  // Configurations: <Config>Has<Block> = 1 when the configuration has the block.
  for (const Config& c : m.configs) {
    for (const std::string& b : m.optional_blocks) {
      o << indent << "localparam bit " << camel(m.name) << "Config" << camel(c.name) << "Has"
        << camel(b) << " = 1'b" << (c.has(b) ? 1 : 0) << ";\n";
    }
  }
  for (const Register& r : m.registers) {
    o << "\n"
      << indent << "// " << r.name << (r.block.empty() ? "" : " (block " + r.block + ")") << "\n";
    auto offset_line = [&](const std::string& name, uint32_t a) {
      o << indent << "localparam logic [" << aw << "-1:0] " << name << "_OFFSET = " << aw << "'h"
        << hex(a, 3) << ";\n";
    };
    offset_line(p + r.name, r.offset);
    if (r.count > 1) {
      o << indent << "localparam int unsigned " << p << r.name << "_COUNT = " << r.count << ";\n";
      o << indent << "localparam int unsigned " << p << r.name << "_STRIDE = " << r.stride << ";\n";
      for (uint32_t i = 0; i < r.count; ++i) {
        offset_line(p + r.name + "_" + std::to_string(i), r.element_offset(i));
      }
    }
    o << indent << "localparam logic [31:0] " << p << r.name << "_RESVAL = 32'h"
      << hex(r.reset(), 8) << ";\n";
    const std::pair<const char*, const char*> masks[] = {
        {"RO", "ro"}, {"RW", "rw"}, {"WO", "wo"}, {"W1C", "w1c"}};
    for (const auto& [suffix, access] : masks) {
      o << indent << "localparam logic [31:0] " << p << r.name << "_" << suffix << "_MASK = 32'h"
        << hex(r.mask_of(access), 8) << ";\n";
    }
    for (const Field& f : r.fields) {
      const std::string fp = p + r.name + "_" + f.name;
      o << indent << "localparam int unsigned " << fp << "_LSB = " << f.lsb << ";\n";
      o << indent << "localparam int unsigned " << fp << "_WIDTH = " << f.width << ";\n";
      o << indent << "localparam logic [" << f.width << "-1:0] " << fp << "_RESVAL = " << f.width
        << "'h" << hex(f.reset, 1) << ";\n";
    }
  }
  o << indent << "// verilator lint_on UNUSEDPARAM\n";
  return o.str();
}

std::string sv_package(const RegMap& m) {
  std::ostringstream o;
  o << "// Generated by tools/regmap_gen from rtl_model/regmap.json. Do not edit.\n"
    << "package " << m.name << "_reg_pkg;\n\n"
    << sv_body(m, "  ") << "\nendpackage\n";
  return o.str();
}

std::string sv_include(const RegMap& m) {
  const std::string guard = upper(m.name) + "_REGS_SVH";
  std::ostringstream o;
  o << "// Generated by tools/regmap_gen from rtl_model/regmap.json. Do not edit.\n"
    << "// The localparams of " << m.name
    << "_reg_pkg, for tools without package support: `include\n"
    << "// inside a module body.\n"
    << "`ifndef " << guard << "\n`define " << guard << "\n\n"
    << sv_body(m, "") << "\n`endif  // " << guard << "\n";
  return o.str();
}

// ---- C++ header.
std::string cpp_access(const std::string& a) {
  if (a == "ro") return "Access::kRo";
  if (a == "rw") return "Access::kRw";
  if (a == "wo") return "Access::kWo";
  return "Access::kW1c";
}
std::string cpp_effect(const std::string& e) {
  if (e == "lut_index_inc") return "Effect::kLutIndexInc";
  if (e == "hist_index_inc") return "Effect::kHistIndexInc";
  if (e == "run_pop") return "Effect::kRunPop";
  return "Effect::kNone";
}
std::string u32(uint32_t v) {
  return "0x" + hex(v, 8) + "u";
}

// Block: kAlways plus one enumerator per optional block.
std::string cpp_blocks(const RegMap& m) {
  std::ostringstream o;
  o << "// The block a register belongs to: kAlways, or an optional block that a\n"
    << "// configuration may leave out (its registers then answer SLVERR).\n"
    << "enum class Block : uint8_t { kAlways";
  for (const std::string& b : m.optional_blocks) o << ", k" << camel(b);
  o << " };\n\n";
  return o.str();
}

// Config: one bool per optional block, and a constant per configuration.
std::string cpp_configs(const RegMap& m) {
  std::ostringstream o;
  o << "// A build-time configuration of the device: the optional blocks it has.\n"
    << "struct Config {\n  const char* name;\n";
  for (const std::string& b : m.optional_blocks) o << "  bool has_" << b << ";\n";
  o << "  constexpr bool has(Block b) const {\n    switch (b) {\n";
  for (const std::string& b : m.optional_blocks) {
    o << "      case Block::k" << camel(b) << ":\n        return has_" << b << ";\n";
  }
  o << "      default:\n        return true;\n    }\n  }\n"
    << "  // The register is present in this configuration.\n"
    << "  constexpr bool has(const Register& r) const { return has(r.block); }\n};\n";
  for (const Config& c : m.configs) {
    o << "inline constexpr Config kConfig" << camel(c.name) << "{\"" << c.name << "\"";
    for (const std::string& b : m.optional_blocks) o << ", " << (c.has(b) ? "true" : "false");
    o << "};\n";
  }
  o << "inline constexpr std::array<Config, " << m.configs.size() << "> kConfigs{{";
  for (size_t i = 0; i < m.configs.size(); ++i) {
    o << (i ? ", " : "") << "kConfig" << camel(m.configs[i].name);
  }
  o << "}};\n\n";
  return o.str();
}

std::string cpp_header(const RegMap& m) {
  std::ostringstream o;
  size_t elements = 0;
  for (const Register& r : m.registers) elements += r.count;
  o << "// Generated by tools/regmap_gen from rtl_model/regmap.json. Do not edit.\n"
    << "// " << m.name << " register map: offsets, field positions, reset values.\n"
    << "#pragma once\n\n#include <array>\n#include <cstdint>\n\n"
    << "namespace " << m.name << "::regs {\n\n"
    << "inline constexpr uint32_t kAddrWidth = " << m.addr_width << ";\n"
    << "inline constexpr uint32_t kAddrMask = "
    << u32(m.addr_width >= 32 ? 0xFFFFFFFFu : (1u << m.addr_width) - 1u) << ";\n";
  for (const Param& prm : m.params) {
    o << "inline constexpr uint32_t k" << prm.name << " = " << prm.value << "u;  // " << prm.desc
      << "\n";
  }
  o << "\n// AXI4-Lite responses.\ninline constexpr uint8_t kRespOkay = 0;\n"
    << "inline constexpr uint8_t kRespSlvErr = 2;\n\n"
    << "enum class Access : uint8_t { kRo, kRw, kWo, kW1c };\n"
    << cpp_blocks(m)
    << "enum class Effect : uint8_t { kNone, kLutIndexInc, kHistIndexInc, kRunPop };\n\n"
    << "struct Field {\n"
    << "  uint32_t lsb;\n  uint32_t width;\n  uint32_t reset;\n  Access access;\n"
    << "  constexpr uint32_t mask() const {\n"
    << "    return (width >= 32 ? 0xFFFFFFFFu : ((1u << width) - 1u)) << lsb;\n  }\n"
    << "  constexpr uint32_t get(uint32_t reg) const { return (reg & mask()) >> lsb; }\n"
    << "  constexpr uint32_t put(uint32_t value) const { return (value << lsb) & mask(); }\n"
    << "};\n\n"
    << "struct Register {\n"
    << "  const char* name;\n  uint32_t offset;\n  uint32_t reset;\n"
    << "  uint32_t ro_mask;\n  uint32_t rw_mask;\n  uint32_t wo_mask;\n  uint32_t w1c_mask;\n"
    << "  Effect read_effect;\n  Effect write_effect;\n  Block block;\n"
    << "  constexpr uint32_t read_mask() const { return ro_mask | rw_mask | w1c_mask; }\n"
    << "  constexpr uint32_t write_mask() const { return rw_mask | wo_mask | w1c_mask; }\n"
    << "};\n\n"
    << "// An array of identical registers at offset + i * stride, i < count.\n"
    << "struct RegArray {\n"
    << "  uint32_t offset;\n  uint32_t stride;\n  uint32_t count;\n"
    << "  constexpr uint32_t at(uint32_t i) const { return offset + i * stride; }\n"
    << "  // The element at addr, or -1.\n"
    << "  constexpr int index(uint32_t addr) const {\n"
    << "    if (addr < offset || (addr - offset) % stride != 0) return -1;\n"
    << "    return (addr - offset) / stride < count ? static_cast<int>((addr - offset) / stride) : "
       "-1;\n"
    << "  }\n"
    << "};\n";
  for (const Register& r : m.registers) {
    o << "\n// " << r.name << ": " << r.desc << "\n"
      << "namespace " << lower(r.name) << " {\n"
      << "inline constexpr uint32_t kOffset = "
      << "0x" << hex(r.offset, 3) << "u;\n";
    if (r.count > 1) {
      o << "inline constexpr uint32_t kCount = " << r.count << "u;\n"
        << "inline constexpr uint32_t kStride = " << r.stride << "u;\n"
        << "inline constexpr RegArray kArray{kOffset, kStride, kCount};\n";
    }
    o << "inline constexpr uint32_t kReset = " << u32(r.reset()) << ";\n";
    for (const Field& f : r.fields) {
      o << "inline constexpr Field k" << camel(f.name) << "{" << f.lsb << ", " << f.width << ", "
        << u32(f.reset) << ", " << cpp_access(f.access) << "};\n";
    }
    o << "}  // namespace " << lower(r.name) << "\n";
  }
  o << "\n// Every register (array elements expanded), in address order of the JSON.\n"
    << "inline constexpr std::array<Register, " << elements << "> kRegisters{{\n";
  for (const Register& r : m.registers) {
    for (uint32_t i = 0; i < r.count; ++i) {
      const std::string name = r.count > 1 ? r.name + "[" + std::to_string(i) + "]" : r.name;
      o << "    {\"" << name << "\", 0x" << hex(r.element_offset(i), 3) << "u, " << u32(r.reset())
        << ", " << u32(r.mask_of("ro")) << ", " << u32(r.mask_of("rw")) << ", "
        << u32(r.mask_of("wo")) << ", " << u32(r.mask_of("w1c")) << ", "
        << cpp_effect(r.read_effect) << ", " << cpp_effect(r.write_effect) << ", "
        << (r.block.empty() ? std::string("Block::kAlways") : "Block::k" + camel(r.block))
        << "},\n";
    }
  }
  o << "}};\n\n"
    << cpp_configs(m) << "// The register at a (word-aligned, in-window) offset, or nullptr.\n"
    << "constexpr const Register* find(uint32_t offset) {\n"
    << "  for (const Register& r : kRegisters) {\n"
    << "    if (r.offset == offset) return &r;\n  }\n  return nullptr;\n}\n\n"
    << "}  // namespace " << m.name << "::regs\n";
  return o.str();
}

// ---- C header for drivers (C99 and C++): offsets, field positions and masks,
// reset values, array counts and strides, as macros.
std::string c_header(const RegMap& m) {
  const std::string p = upper(m.name) + "_";
  const std::string guard = p + "REGS_H_";
  std::ostringstream o;
  o << "/* Generated by tools/regmap_gen from rtl_model/regmap.json. Do not edit. */\n"
    << "/* " << m.name << " register map for drivers: byte offsets, field LSB/width/mask,\n"
    << "   reset values; arrays: " << p << "<REG>_OFFSET_I(i). */\n"
    << "#ifndef " << guard << "\n#define " << guard << "\n\n#include <stdint.h>\n\n"
    << "#define " << p << "ADDR_WIDTH " << m.addr_width << "u\n"
    << "#define " << p << "RESP_OKAY 0u\n#define " << p << "RESP_SLVERR 2u\n";
  for (const Param& prm : m.params) {
    o << "#define " << p << "PARAM_" << upper(prm.name) << " " << prm.value << "u\n";
  }
  for (const Config& c : m.configs) {
    for (const std::string& b : m.optional_blocks) {
      o << "#define " << p << "CONFIG_" << upper(c.name) << "_HAS_" << upper(b) << " "
        << (c.has(b) ? 1 : 0) << "\n";
    }
  }
  for (const Register& r : m.registers) {
    const std::string rp = p + r.name;
    o << "\n/* " << r.name << " */\n"
      << "#define " << rp << "_OFFSET 0x" << hex(r.offset, 3) << "u\n";
    if (r.count > 1) {
      o << "#define " << rp << "_COUNT " << r.count << "u\n"
        << "#define " << rp << "_STRIDE " << r.stride << "u\n"
        << "#define " << rp << "_OFFSET_I(i) (" << rp << "_OFFSET + (uint32_t)(i) * " << rp
        << "_STRIDE)\n";
    }
    o << "#define " << rp << "_RESVAL 0x" << hex(r.reset(), 8) << "u\n";
    const std::pair<const char*, const char*> masks[] = {
        {"RO", "ro"}, {"RW", "rw"}, {"WO", "wo"}, {"W1C", "w1c"}};
    for (const auto& [suffix, access] : masks) {
      if (r.mask_of(access) != 0) {
        o << "#define " << rp << "_" << suffix << "_MASK 0x" << hex(r.mask_of(access), 8) << "u\n";
      }
    }
    for (const Field& fl : r.fields) {
      const std::string fp = rp + "_" + fl.name;
      o << "#define " << fp << "_LSB " << fl.lsb << "u\n"
        << "#define " << fp << "_WIDTH " << fl.width << "u\n"
        << "#define " << fp << "_MASK 0x" << hex(fl.mask(), 8) << "u\n"
        << "#define " << fp << "_RESVAL 0x" << hex(fl.reset, 1) << "u\n";
    }
  }
  o << "\n#endif /* " << guard << " */\n";
  return o.str();
}

// ---- Markdown.
std::string md_escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '|')
      out += "\\|";
    else
      out += c;
  }
  return out;
}

std::string markdown(const RegMap& m) {
  std::ostringstream o;
  o << "# " << m.name << " registers\n\n"
    << "<!-- Generated by tools/regmap_gen from rtl_model/regmap.json. Do not edit: run\n"
    << "     `cmake --build <build> --target update_register_doc`. -->\n\n"
    << md_escape(m.desc) << "\n\n"
    << "Address window: " << m.addr_width << " bits (0x000..0x" << hex((1u << m.addr_width) - 1, 3)
    << "); the device decodes only these bits. Access types per field: `ro` read-only, `rw`\n"
    << "read/write, `wo` write-only (reads 0), `w1c` write 1 to clear. Bus rules (see\n"
    << "docs/blocks/ceilnav_top.md): an address with no register, a misaligned address, a\n"
    << "write with `wstrb != 4'b1111` and a write to a register without writable fields answer\n"
    << "SLVERR and have no effect.\n\n"
    << "Generated from the same source: the SystemVerilog package `" << m.name
    << "_reg_pkg`, the C++\n"
    << "header `" << m.name << "/regs.hpp` and the C99 header `" << m.name << "/" << m.name
    << "_regs.h` for drivers\n"
    << "(offsets, field LSB/width/mask, reset values, `<REG>_OFFSET_I(i)` for arrays); both\n"
    << "headers are installed with the package (docs/architecture.md).\n\n";
  if (!m.params.empty()) {
    o << "| parameter | default | description |\n|---|---|---|\n";
    for (const Param& p : m.params) {
      o << "| " << p.name << " | " << p.value << " | " << md_escape(p.desc) << " |\n";
    }
    o << "\n";
  }
  if (!m.configs.empty()) {
    o << "## Configurations\n\nThe device is built in one of these configurations (the SV top's\n"
      << "parameters, `stream::CeilnavTop`'s `regs::Config`); a register of an optional block "
         "that\n"
      << "the configuration leaves out answers SLVERR like an unmapped address.\n\n"
      << "| configuration |";
    for (const std::string& b : m.optional_blocks) o << " " << b << " |";
    o << "\n|---|";
    for (size_t i = 0; i < m.optional_blocks.size(); ++i) o << "---|";
    o << "\n";
    for (const Config& c : m.configs) {
      o << "| " << c.name << " |";
      for (const std::string& b : m.optional_blocks) o << (c.has(b) ? " yes |" : " no |");
      o << "\n";
    }
    o << "\n";
  }
  o << "## Summary\n\n| offset | register | access | reset | side effect | description |\n"
    << "|---|---|---|---|---|---|\n";
  for (const Register& r : m.registers) {
    std::string offset = "0x" + hex(r.offset, 3);
    if (r.count > 1) {
      offset += " + 0x" + hex(r.stride, 1) + "*i (i < " + std::to_string(r.count) + ")";
    }
    std::string effect;
    if (r.read_effect != "none") effect += "read: " + r.read_effect;
    if (r.write_effect != "none")
      effect += std::string(effect.empty() ? "" : ", ") + "write: " + r.write_effect;
    const std::string first_sentence = r.desc.substr(0, r.desc.find(". ") + 1);
    o << "| " << offset << " | " << (r.count > 1 ? r.name + "[i]" : r.name) << " | "
      << r.access_summary() << " | 0x" << hex(r.reset(), 8) << " | " << effect << " | "
      << md_escape(r.desc.find(". ") == std::string::npos ? r.desc : first_sentence) << " |\n";
  }
  o << "\n## Registers\n";
  for (const Register& r : m.registers) {
    o << "\n### " << r.name << (r.count > 1 ? "[i]" : "") << " (0x" << hex(r.offset, 3);
    if (r.count > 1) o << " + 0x" << hex(r.stride, 1) << "*i, i = 0.." << r.count - 1;
    o << ")\n\n" << md_escape(r.desc) << "\n\n";
    if (!r.block.empty()) {
      o << "Present only in configurations with the optional block `" << r.block << "`.\n\n";
    }
    o << ""
      << "| bits | field | access | reset | description |\n|---|---|---|---|---|\n";
    for (const Field& f : r.fields) {
      const std::string bits =
          f.width == 1 ? std::to_string(f.lsb)
                       : std::to_string(f.lsb + f.width - 1) + ":" + std::to_string(f.lsb);
      std::string reset = "0x" + hex(f.reset, 1);
      if (!f.param.empty()) reset += " (" + f.param + ")";
      o << "| " << bits << " | " << f.name << " | " << f.access << " | " << reset << " | "
        << md_escape(f.desc) << " |\n";
    }
  }
  return o.str();
}

void write_if_changed(const std::filesystem::path& path, const std::string& text) {
  // Leave unchanged outputs untouched so that dependants are not rebuilt.
  {
    std::ifstream in(path, std::ios::binary);
    if (in) {
      std::stringstream old;
      old << in.rdbuf();
      if (old.str() == text) return;
    }
  }
  std::filesystem::create_directories(path.parent_path());
  std::ofstream out(path, std::ios::binary);
  out << text;
  if (!out) fail("cannot write " + path.string());
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::cerr << "usage: regmap_gen <regmap.json> <output dir>\n";
    return 2;
  }
  try {
    std::ifstream in(argv[1]);
    if (!in) fail(std::string("cannot read ") + argv[1]);
    const RegMap m = parse(json::parse(in));
    const std::filesystem::path out = argv[2];
    write_if_changed(out / (m.name + "_reg_pkg.sv"), sv_package(m));
    write_if_changed(out / (m.name + "_regs.svh"), sv_include(m));
    write_if_changed(out / m.name / "regs.hpp", cpp_header(m));
    write_if_changed(out / m.name / (m.name + "_regs.h"), c_header(m));
    write_if_changed(out / "registers.md", markdown(m));
  } catch (const std::exception& e) {
    std::cerr << "regmap_gen: " << argv[1] << ": " << e.what() << "\n";
    return 1;
  }
  return 0;
}
