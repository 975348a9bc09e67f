// The register map as the generators read it from rtl_model/regmap.json:
// registers, fields, parameters, optional blocks and configurations, side
// effects and the interrupt registers, validated by parse(). Used by
// regmap_gen (package, headers, doc) and by the register block emitters
// (regblock_emit.cpp).
#pragma once

#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace regmap {

using nlohmann::json;

struct Field {
  std::string name;
  uint32_t lsb = 0;
  uint32_t width = 1;
  std::string access;  // ro, rw, wo, w1c
  uint32_t reset = 0;
  std::string param;  // reset value taken from this parameter (documentation)
  // ro only: the value is the reset value (a constant of the design) instead
  // of a hardware input of the register block.
  bool constant = false;
  std::string desc;

  bool hw_input() const { return access == "ro" && !constant; }

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
  std::string block;                 // optional block the register belongs to ("" = always present)
  std::string read_effect = "none";  // effect of an OKAY read (see Effect)
  std::string write_effect = "none";  // effect of an OKAY write
  // The value is not held by the register block: it is the hardware input
  // one edge after the read strobe (a block's synchronous read port).
  bool external = false;
  // The register is a word of a read port (see Port) instead of a field input.
  std::string port;
  std::vector<Field> fields;

  bool has_access(const std::string& access) const { return mask_of(access) != 0; }

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

// A side effect of a register access. `incr` (REG.FIELD, an rw field of a
// one-element register): the access increments that field by 1 (mod 2^width)
// unless the same edge writes it. Every effect is also a strobe of the
// register block (reg2hw: `re` for a read effect, `we` for a write effect).
struct Effect {
  std::string name;
  std::string incr_register;  // "" if the effect is a strobe only
  std::string incr_field;
  std::string desc;
};

// A read port: registers whose words the hardware serves from its own store
// (a RAM): the register block strobes the port with the word's index on the
// sample edge and takes the 32-bit word one edge later. With `wait`, the
// hardware can hold a read (ready = 0) until its store is consistent.
struct Port {
  std::string name;
  bool wait = false;
  std::string desc;
};

// The interrupt registers: state (w1c, hardware-set), enable (rw) and test
// (wo, sets state), with the same fields; irq = |(state & enable).
struct Interrupts {
  std::string state;
  std::string enable;
  std::string test;
};

struct RegMap {
  std::string name;
  std::string desc;
  uint32_t addr_width = 0;
  std::vector<Param> params;
  std::vector<std::string> optional_blocks;  // blocks a configuration may leave out
  std::vector<Config> configs;
  std::vector<Register> registers;
  std::vector<Effect> effects;
  std::vector<Port> ports;
  Interrupts interrupts;  // names empty if the map has no interrupt

  const Register& reg(const std::string& name) const;
  const Effect* effect(const std::string& name) const;
  const Port* port(const std::string& name) const;
};

[[noreturn]] void fail(const std::string& msg);
uint32_t parse_u32(const json& j, const std::string& what);
std::string upper(std::string s);
std::string lower(std::string s);
std::string camel(const std::string& s);  // FRAME_DONE -> FrameDone
bool valid_name(const std::string& s);
std::string hex(uint32_t v, int digits);

// The map in `j`, validated; throws std::runtime_error with a message.
RegMap parse(const json& j);

// The register block (regblock_emit.cpp): the reg2hw / hw2reg struct types
// for the SV package, the SV module and its C++ cycle model.
std::string sv_regblock_types(const RegMap& m, const std::string& indent);
std::string sv_regblock(const RegMap& m);
std::string cpp_regblock(const RegMap& m);

}  // namespace regmap
