// Parsing and validation of rtl_model/regmap.json (see regmap_model.hpp).
#include "regmap_model.hpp"

#include <cctype>
#include <cstdio>
#include <map>
#include <stdexcept>

namespace regmap {

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
  for (const json& e : j.value("effects", json::array())) {
    Effect eff;
    eff.name = e.at("name").get<std::string>();
    if (eff.name.empty() || eff.name == "none" ||
        !std::islower(static_cast<unsigned char>(eff.name[0]))) {
      fail("bad effect name " + eff.name);
    }
    if (m.effect(eff.name) != nullptr) fail("effect " + eff.name + " defined twice");
    const std::string incr = e.value("incr", "");
    if (!incr.empty()) {
      const size_t dot = incr.find('.');
      if (dot == std::string::npos) fail("effect " + eff.name + ": incr is not REG.FIELD");
      eff.incr_register = incr.substr(0, dot);
      eff.incr_field = incr.substr(dot + 1);
    }
    eff.desc = e.value("desc", "");
    m.effects.push_back(eff);
  }
  for (const json& pj : j.value("ports", json::array())) {
    Port port{pj.at("name").get<std::string>(), pj.value("wait", false), pj.value("desc", "")};
    if (port.name.empty() || !std::islower(static_cast<unsigned char>(port.name[0]))) {
      fail("bad port name " + port.name);
    }
    if (m.port(port.name) != nullptr) fail("port " + port.name + " defined twice");
    m.ports.push_back(port);
  }
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
      if (e != "none" && m.effect(e) == nullptr) fail(where + ": unknown side effect " + e);
    }
    reg.external = r.value("external", false);
    reg.port = r.value("port", "");
    if (!reg.port.empty() && m.port(reg.port) == nullptr)
      fail(where + ": unknown port " + reg.port);
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
      const std::string hw = fj.value("hw", "");
      if (!hw.empty() && hw != "const") fail(fwhere + ": unknown hw kind " + hw);
      f.constant = hw == "const";
      if (f.constant && f.access != "ro") fail(fwhere + ": only an ro field can be a constant");
      f.desc = fj.value("desc", "");
      if ((used & f.mask()) != 0) fail(fwhere + ": overlaps another field");
      used |= f.mask();
      reg.fields.push_back(f);
    }
    if (reg.fields.empty()) fail(where + ": no fields");
    m.registers.push_back(reg);
  }
  // What the register block generator supports.
  for (const Register& r : m.registers) {
    const std::string where = "register " + r.name;
    if (r.count > 1 && (r.has_access("rw") || r.has_access("wo") || r.has_access("w1c"))) {
      fail(where + ": an array may hold ro fields only");
    }
    if (!r.port.empty()) {
      const bool all_inputs = std::all_of(r.fields.begin(), r.fields.end(),
                                          [](const Field& f) { return f.hw_input(); });
      if (!all_inputs || r.external) {
        fail(where + ": a port register has ro hardware fields only and is not external");
      }
    }
    if (r.external) {
      if (r.count > 1 || r.fields.size() != 1 || !r.fields[0].hw_input()) {
        fail(where + ": an external register is one register with one ro hardware field");
      }
    }
  }
  for (const Port& p : m.ports) {
    for (const Register& r : m.registers) {
      if (lower(r.name) == p.name) fail("port " + p.name + " has a register's name");
    }
  }
  for (const Effect& e : m.effects) {
    if (e.incr_register.empty()) continue;
    const auto it = std::find_if(m.registers.begin(), m.registers.end(),
                                 [&](const Register& r) { return r.name == e.incr_register; });
    if (it == m.registers.end() || it->count != 1) {
      fail("effect " + e.name + ": no one-element register " + e.incr_register);
    }
    const auto f = std::find_if(it->fields.begin(), it->fields.end(),
                                [&](const Field& x) { return x.name == e.incr_field; });
    if (f == it->fields.end() || f->access != "rw") {
      fail("effect " + e.name + ": " + e.incr_register + "." + e.incr_field +
           " is not an rw field");
    }
  }
  if (j.contains("interrupts")) {
    const json& ij = j.at("interrupts");
    m.interrupts = {ij.at("state").get<std::string>(), ij.at("enable").get<std::string>(),
                    ij.at("test").get<std::string>()};
    const std::pair<std::string, std::string> roles[] = {
        {m.interrupts.state, "w1c"}, {m.interrupts.enable, "rw"}, {m.interrupts.test, "wo"}};
    const Register& state = m.reg(m.interrupts.state);
    for (const auto& [name, access] : roles) {
      const Register& r = m.reg(name);
      if (r.count != 1 || r.mask_of(access) != state.mask_of("w1c") ||
          r.fields.size() != state.fields.size()) {
        fail("interrupts: " + name + " must have the fields of " + state.name + ", all " + access);
      }
      for (size_t i = 0; i < r.fields.size(); ++i) {
        if (r.fields[i].name != state.fields[i].name || r.fields[i].lsb != state.fields[i].lsb) {
          fail("interrupts: " + name + " must have the fields of " + state.name);
        }
      }
    }
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

const Register& RegMap::reg(const std::string& reg_name) const {
  const auto it = std::find_if(registers.begin(), registers.end(),
                               [&](const Register& r) { return r.name == reg_name; });
  if (it == registers.end()) fail("no register " + reg_name);
  return *it;
}

const Port* RegMap::port(const std::string& port_name) const {
  const auto it =
      std::find_if(ports.begin(), ports.end(), [&](const Port& p) { return p.name == port_name; });
  return it == ports.end() ? nullptr : &*it;
}

const Effect* RegMap::effect(const std::string& effect_name) const {
  const auto it = std::find_if(effects.begin(), effects.end(),
                               [&](const Effect& e) { return e.name == effect_name; });
  return it == effects.end() ? nullptr : &*it;
}

}  // namespace regmap
