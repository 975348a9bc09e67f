// The register block in two languages from one map: the SystemVerilog module
// <name>_regblock with its reg2hw / hw2reg packed structs, and its C++ cycle
// model (class RegBlock of <name>/regblock.hpp). Both are emitted from the same
// walk over the registers so that they cannot disagree on decode or behaviour;
// the co-simulation of the device top checks them against each other.
//
// Behaviour (docs/registers.md, docs/blocks/ceilnav_top.md):
// * AXI4-Lite: AW and W are taken together, one write at a time; B on the next
//   edge. One read in flight: AR on edge e, the register is sampled on edge
//   e+1 (its read strobe and effect happen there), rvalid rises on edge e+2.
// * A write is OKAY if the address is a present register with a writable
//   field and wstrb = 4'hF; anything else answers SLVERR and changes nothing.
//   A read is OKAY if the address is a present register (write-only fields
//   read 0).
// * rw: stored, out as reg2hw.<reg>.<field>. wo: the write data of the edge,
//   valid with reg2hw.<reg>.we. w1c: stored, set by hw2reg.<reg>.<field> (a
//   set wins over a clear on the same edge). ro: a constant, or the hardware
//   input hw2reg.<reg>.<field> as it is before the sample edge; an external
//   register's input is taken one edge after its read strobe instead.
// * Effects: reg2hw.<reg>.re (read) / .we (write) strobes; an `incr` effect
//   adds 1 to an rw field unless the same edge writes it.
// * Interrupts: the test register sets the state register; irq_o =
//   |(state & enable), irq_rise_o is high on the edge on which irq_o rises.
#include <algorithm>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "regmap_model.hpp"

namespace regmap {

namespace {

// Names that cannot be struct members in SystemVerilog or C++.
std::string member(const std::string& field_or_reg) {
  static const char* const kReserved[] = {
      "class", "default", "int",  "logic",  "bit",    "reg",   "wire",   "struct", "union",
      "enum",  "type",    "new",  "delete", "this",   "const", "table",  "input",  "output",
      "begin", "end",     "case", "module", "assign", "event", "string", "signed", "unsigned"};
  std::string n = lower(field_or_reg);
  for (const char* r : kReserved) {
    if (n == r) return n + "_";
  }
  return n;
}

// One addressable word: element `index` of register `reg`.
struct Word {
  const Register* reg;
  uint32_t index;
  uint32_t offset;
};

std::vector<Word> words(const RegMap& m) {
  std::vector<Word> w;
  for (const Register& r : m.registers) {
    for (uint32_t i = 0; i < r.count; ++i) w.push_back({&r, i, r.element_offset(i)});
  }
  return w;
}

bool is_interrupt(const RegMap& m, const Register& r) {
  return r.name == m.interrupts.state || r.name == m.interrupts.enable ||
         r.name == m.interrupts.test;
}
bool writable(const Register& r) {
  return r.mask_of("rw") != 0 || r.mask_of("wo") != 0 || r.mask_of("w1c") != 0;
}
bool stored(const Field& f) {
  return f.access == "rw" || f.access == "w1c";
}
// reg2hw of a register: rw and wo fields, `we`, `re` (not the interrupt registers).
bool has_we(const RegMap& m, const Register& r) {
  return !is_interrupt(m, r) && (r.mask_of("wo") != 0 || r.write_effect != "none");
}
bool has_re(const Register& r) {
  return r.read_effect != "none";
}
std::vector<const Field*> reg2hw_fields(const RegMap& m, const Register& r) {
  std::vector<const Field*> out;
  if (is_interrupt(m, r)) return out;
  for (const Field& f : r.fields) {
    if (f.access == "rw" || f.access == "wo") out.push_back(&f);
  }
  return out;
}
bool in_reg2hw(const RegMap& m, const Register& r) {
  return !reg2hw_fields(m, r).empty() || has_we(m, r) || has_re(r);
}
// hw2reg of a register: ro hardware inputs and w1c set inputs.
std::vector<const Field*> hw2reg_fields(const Register& r) {
  std::vector<const Field*> out;
  if (!r.port.empty()) return out;  // served through the port
  for (const Field& f : r.fields) {
    if (f.hw_input() || f.access == "w1c") out.push_back(&f);
  }
  return out;
}
// The effects that increment `r.f`: (register with the effect, true if a read effect).
std::vector<std::pair<const Register*, bool>> incrementers(const RegMap& m, const Register& r,
                                                           const Field& f) {
  std::vector<std::pair<const Register*, bool>> out;
  for (const Register& src : m.registers) {
    for (const bool read : {true, false}) {
      const Effect* e = m.effect(read ? src.read_effect : src.write_effect);
      if (e != nullptr && e->incr_register == r.name && e->incr_field == f.name) {
        out.push_back({&src, read});
      }
    }
  }
  return out;
}

// The word index of a one-element register.
std::string word_of_name(const RegMap& m, const Register& r) {
  size_t e = 0;
  for (const Register& x : m.registers) {
    if (&x == &r) return std::to_string(e);
    e += x.count;
  }
  fail("no register " + r.name);
}

// The words of port `p`, in index order.
std::vector<size_t> port_words(const std::vector<Word>& ws, const std::string& p) {
  std::vector<size_t> out;
  for (size_t e = 0; e < ws.size(); ++e) {
    if (ws[e].reg->port == p) out.push_back(e);
  }
  return out;
}
uint32_t index_bits(size_t words) {
  uint32_t b = 1;
  while ((size_t{1} << b) < words) ++b;
  return b;
}

std::string width_decl(uint32_t w) {
  return w == 1 ? "logic" : "logic [" + std::to_string(w - 1) + ":0]";
}
std::string present_expr(const Register& r) {
  return r.block.empty() ? "1'b1" : "Has" + camel(r.block);
}
std::string sv_hex32(uint32_t v) {
  return "32'h" + hex(v, 8);
}

}  // namespace

// ---- SystemVerilog: the reg2hw / hw2reg types (package body).
std::string sv_regblock_types(const RegMap& m, const std::string& indent) {
  const std::string n = m.name;
  std::ostringstream o;
  o << indent << "// Register block interface (" << n << "_regblock): reg2hw drives the design,\n"
    << indent << "// hw2reg feeds the register block.\n";
  for (const Register& r : m.registers) {
    if (!in_reg2hw(m, r)) continue;
    o << indent << "typedef struct packed {\n";
    for (const Field* f : reg2hw_fields(m, r)) {
      o << indent << "  " << width_decl(f->width) << " " << member(f->name) << ";  // " << f->access
        << "\n";
    }
    if (has_we(m, r)) o << indent << "  logic we;  // write strobe\n";
    if (has_re(r)) o << indent << "  logic re;  // read strobe (sample edge)\n";
    o << indent << "} " << n << "_reg2hw_" << member(r.name) << "_t;\n";
  }
  const std::vector<Word> ws = words(m);
  for (const Port& p : m.ports) {
    o << indent << "typedef struct packed {\n"
      << indent << "  " << width_decl(index_bits(port_words(ws, p.name).size()))
      << " index;  // word of the port (with re)\n"
      << indent << "  logic re;  // read strobe (sample edge)\n"
      << indent << "} " << n << "_reg2hw_" << p.name << "_port_t;\n";
  }
  o << indent << "typedef struct packed {\n";
  for (const Register& r : m.registers) {
    if (in_reg2hw(m, r)) {
      o << indent << "  " << n << "_reg2hw_" << member(r.name) << "_t " << member(r.name) << ";\n";
    }
  }
  for (const Port& p : m.ports) {
    o << indent << "  " << n << "_reg2hw_" << p.name << "_port_t " << p.name << ";\n";
  }
  o << indent << "} " << n << "_reg2hw_t;\n\n";
  for (const Register& r : m.registers) {
    const auto fields = hw2reg_fields(r);
    if (fields.empty()) continue;
    o << indent << "typedef struct packed {\n";
    for (const Field* f : fields) {
      o << indent << "  ";
      if (r.count > 1) {
        o << "logic [" << r.count - 1 << ":0][" << f->width - 1 << ":0]";
      } else {
        o << width_decl(f->width);
      }
      o << " " << member(f->name) << ";  // " << (f->access == "w1c" ? "set" : "value") << "\n";
    }
    o << indent << "} " << n << "_hw2reg_" << member(r.name) << "_t;\n";
  }
  for (const Port& p : m.ports) {
    o << indent << "typedef struct packed {\n"
      << indent << "  logic [31:0] data;  // the word, one edge after re\n";
    if (p.wait) o << indent << "  logic ready;  // 0: hold a read of the port\n";
    o << indent << "} " << n << "_hw2reg_" << p.name << "_port_t;\n";
  }
  o << indent << "typedef struct packed {\n";
  for (const Register& r : m.registers) {
    if (!hw2reg_fields(r).empty()) {
      o << indent << "  " << n << "_hw2reg_" << member(r.name) << "_t " << member(r.name) << ";\n";
    }
  }
  for (const Port& p : m.ports) {
    o << indent << "  " << n << "_hw2reg_" << p.name << "_port_t " << p.name << ";\n";
  }
  o << indent << "} " << n << "_hw2reg_t;\n";
  return o.str();
}

// ---- SystemVerilog: the register block module.
std::string sv_regblock(const RegMap& m) {
  const std::string n = m.name;
  const std::string pkg = n + "_reg_pkg";
  const std::vector<Word> ws = words(m);
  const uint32_t aw = m.addr_width;
  std::ostringstream o;
  o << "// Generated by tools/regmap_gen from rtl_model/regmap.json. Do not edit.\n"
    << "// " << n << "_regblock: the AXI4-Lite register file of the device (decode,\n"
    << "// storage, read multiplexer, side-effect strobes, interrupt). Behaviour:\n"
    << "// tools/regblock_emit.cpp and docs/registers.md; the C++ twin is\n"
    << "// " << n << "/regblock.hpp (stream::RegBlock), generated from the same map.\n"
    << "module " << n << "_regblock #(\n";
  for (size_t i = 0; i < m.optional_blocks.size(); ++i) {
    o << "  parameter bit Has" << camel(m.optional_blocks[i]) << " = 1'b1"
      << (i + 1 < m.optional_blocks.size() ? "," : "") << "\n";
  }
  o << ") (\n"
    << "  input  logic        clk_i,\n  input  logic        rst_ni,\n\n"
    << "  input  logic [31:0] s_axil_awaddr_i,\n  input  logic        s_axil_awvalid_i,\n"
    << "  output logic        s_axil_awready_o,\n  input  logic [31:0] s_axil_wdata_i,\n"
    << "  input  logic [3:0]  s_axil_wstrb_i,\n  input  logic        s_axil_wvalid_i,\n"
    << "  output logic        s_axil_wready_o,\n  output logic [1:0]  s_axil_bresp_o,\n"
    << "  output logic        s_axil_bvalid_o,\n  input  logic        s_axil_bready_i,\n"
    << "  input  logic [31:0] s_axil_araddr_i,\n  input  logic        s_axil_arvalid_i,\n"
    << "  output logic        s_axil_arready_o,\n  output logic [31:0] s_axil_rdata_o,\n"
    << "  output logic [1:0]  s_axil_rresp_o,\n  output logic        s_axil_rvalid_o,\n"
    << "  input  logic        s_axil_rready_i,\n\n"
    << "  output " << pkg << "::" << n << "_reg2hw_t reg2hw_o,\n"
    << "  input  " << pkg << "::" << n << "_hw2reg_t hw2reg_i,\n\n"
    << "  output logic        irq_o,       // |(state & enable)\n"
    << "  output logic        irq_rise_o   // irq_o rises on this edge\n"
    << ");\n\n"
    << "  localparam int unsigned AddrBits = " << aw << ";\n"
    << "  localparam int unsigned NumWords = " << ws.size() << ";\n"
    << "  localparam logic [1:0] RespOkay = 2'b00;\n"
    << "  localparam logic [1:0] RespSlvErr = 2'b10;\n\n";

  // Word table.
  o << "  // Words: index, register[element], offset.\n";
  for (size_t e = 0; e < ws.size(); ++e) {
    o << "  localparam logic [AddrBits-1:0] Word" << e << " = " << aw << "'h"
      << hex(ws[e].offset, 3) << ";  // " << ws[e].reg->name
      << (ws[e].reg->count > 1 ? "[" + std::to_string(ws[e].index) + "]" : "") << "\n";
  }
  o << "\n  // A word of an absent optional block decodes as no register.\n"
    << "  logic [NumWords-1:0] present;\n";
  for (size_t e = 0; e < ws.size(); ++e) {
    o << "  assign present[" << e << "] = " << present_expr(*ws[e].reg) << ";\n";
  }

  o << "\n  // AXI4-Lite channel state.\n"
    << "  logic                awready_q, bvalid_q, arready_q, rvalid_q;\n"
    << "  logic [1:0]          bresp_q, rresp_q, rd_resp_q;\n"
    << "  logic [1:0]          rd_stage_q;  // 0 idle, 1 sample on this edge, 2 respond, 3 rvalid\n"
    << "  logic [NumWords-1:0] rd_sel_q;    // one-hot word of the read in flight (none: SLVERR)\n"
    << "  logic [31:0]         rd_data_q, rdata_q;\n";
  std::vector<size_t> ext;
  for (size_t e = 0; e < ws.size(); ++e) {
    if (ws[e].reg->external) ext.push_back(e);
  }
  if (!ext.empty()) {
    o << "  logic [" << ext.size() - 1
      << ":0]          rd_ext_q;  // the response is external word k\n";
  }
  if (!m.ports.empty()) {
    o << "  logic [" << m.ports.size() - 1
      << ":0]          rd_port_q;  // the response is port k's data\n";
  }
  // Ports: the words of each, the strobe and index, the hold of a waiting port.
  o << "\n  // Read ports: a read of a port word is served by the hardware (index with\n"
    << "  // re on the sample edge, the word one edge later); a port that is not ready\n"
    << "  // holds the read in the sample stage.\n  logic rd_stall;\n";
  std::string stall;
  for (size_t k = 0; k < m.ports.size(); ++k) {
    const Port& p = m.ports[k];
    const auto pw = port_words(ws, p.name);
    const uint32_t ib = index_bits(pw.size());
    o << "  logic rd_in_" << p.name << ";\n  logic [" << ib - 1 << ":0] " << p.name
      << "_index;\n  always_comb begin\n    rd_in_" << p.name << " = 1'b0;\n    " << p.name
      << "_index = '0;\n";
    for (size_t i = 0; i < pw.size(); ++i) {
      o << "    if (rd_sel_q[" << pw[i] << "]) begin\n      rd_in_" << p.name << " = 1'b1;\n      "
        << p.name << "_index = " << ib << "'d" << i << ";\n    end\n";
    }
    o << "  end\n";
    if (p.wait) {
      stall += std::string(stall.empty() ? "" : " | ") + "(rd_in_" + p.name + " & ~hw2reg_i." +
               p.name + ".ready)";
    }
  }
  o << "  assign rd_stall = (rd_stage_q == 2'd1) & " << (stall.empty() ? "1'b0" : "(" + stall + ")")
    << ";\n";

  o << "\n  logic                aw_hs, b_hs, ar_hs, r_hs, rd_sample;\n"
    << "  logic [AddrBits-1:0] wr_addr, ar_addr;\n"
    << "  logic [31:0]         wdata;\n"
    << "  assign aw_hs     = awready_q & s_axil_awvalid_i & s_axil_wvalid_i;  // wready == "
       "awready\n"
    << "  assign b_hs      = bvalid_q & s_axil_bready_i;\n"
    << "  assign ar_hs     = arready_q & s_axil_arvalid_i;\n"
    << "  assign r_hs      = rvalid_q & s_axil_rready_i;\n"
    << "  assign rd_sample = (rd_stage_q == 2'd1) & ~rd_stall;\n"
    << "  assign wr_addr   = s_axil_awaddr_i[AddrBits-1:0];\n"
    << "  assign ar_addr   = s_axil_araddr_i[AddrBits-1:0];\n"
    << "  assign wdata     = s_axil_wdata_i;\n\n";

  // Decode.
  o << "  // Decode: one-hot over the present words; a write needs a writable field.\n"
    << "  logic [NumWords-1:0] ar_match, wr_match;\n";
  for (size_t e = 0; e < ws.size(); ++e) {
    o << "  assign ar_match[" << e << "] = present[" << e << "] & (ar_addr == Word" << e << ");\n";
    if (writable(*ws[e].reg)) {
      o << "  assign wr_match[" << e << "] = present[" << e << "] & (wr_addr == Word" << e
        << ");\n";
    } else {
      o << "  assign wr_match[" << e << "] = 1'b0;  // no writable field\n";
    }
  }
  o << "  logic wr_err, wr_ok;\n"
    << "  assign wr_err = ~(|wr_match) | (s_axil_wstrb_i != 4'hF);\n"
    << "  assign wr_ok  = aw_hs & ~wr_err;\n";
  // Per-register write / read strobes.
  std::map<std::string, size_t> word_of;  // one-element registers
  for (size_t e = 0; e < ws.size(); ++e) {
    if (ws[e].reg->count == 1) word_of[ws[e].reg->name] = e;
  }
  for (const Register& r : m.registers) {
    if (r.count == 1 && writable(r)) {
      o << "  logic we_" << member(r.name) << ";\n  assign we_" << member(r.name)
        << " = wr_ok & wr_match[" << word_of[r.name] << "];\n";
    }
    if (r.count == 1 && has_re(r)) {
      o << "  logic re_" << member(r.name) << ";\n  assign re_" << member(r.name)
        << " = rd_sample & rd_sel_q[" << word_of[r.name] << "];\n";
    }
  }

  // Storage.
  o << "\n  // Stored fields: next value (_d) and flop (_q).\n";
  for (const Register& r : m.registers) {
    for (const Field& f : r.fields) {
      if (!stored(f)) continue;
      const std::string s = member(r.name) + "_" + member(f.name);
      o << "  " << width_decl(f.width) << " " << s << "_d, " << s << "_q;\n";
    }
  }
  o << "  always_comb begin\n";
  for (const Register& r : m.registers) {
    for (const Field& f : r.fields) {
      if (!stored(f)) continue;
      const std::string s = member(r.name) + "_" + member(f.name);
      const std::string wslice =
          "wdata[" + std::to_string(f.lsb) + " +: " + std::to_string(f.width) + "]";
      if (f.access == "rw") {
        o << "    " << s << "_d = " << s << "_q;\n"
          << "    if (we_" << member(r.name) << ") begin\n"
          << "      " << s << "_d = " << wslice << ";\n    end";
        for (const auto& [src, read] : incrementers(m, r, f)) {
          o << " else if (" << (read ? "re_" : "we_") << member(src->name) << ") begin\n"
            << "      " << s << "_d = " << s << "_q + " << f.width << "'d1;\n    end";
        }
        o << "\n";
      } else {  // w1c: a set wins over a clear
        std::string set = "hw2reg_i." + member(r.name) + "." + member(f.name);
        if (r.name == m.interrupts.state) {
          const Register& t = m.reg(m.interrupts.test);
          set += " | (we_" + member(t.name) + " ? " + wslice + " : " + std::to_string(f.width) +
                 "'d0)";
        }
        o << "    " << s << "_d = (" << s << "_q & ~(we_" << member(r.name) << " ? " << wslice
          << " : " << f.width << "'d0)) | " << set << ";\n";
      }
    }
  }
  o << "  end\n\n  always_ff @(posedge clk_i) begin\n    if (!rst_ni) begin\n";
  for (const Register& r : m.registers) {
    for (const Field& f : r.fields) {
      if (!stored(f)) continue;
      o << "      " << member(r.name) << "_" << member(f.name) << "_q <= " << f.width << "'h"
        << hex(f.reset, 1) << ";\n";
    }
  }
  o << "    end else begin\n";
  for (const Register& r : m.registers) {
    for (const Field& f : r.fields) {
      if (!stored(f)) continue;
      const std::string s = member(r.name) + "_" + member(f.name);
      o << "      " << s << "_q <= " << s << "_d;\n";
    }
  }
  o << "    end\n  end\n\n";

  // reg2hw.
  o << "  // reg2hw: stored values, the write data and strobes of this edge.\n";
  for (const Register& r : m.registers) {
    if (!in_reg2hw(m, r)) continue;
    const std::string base = "reg2hw_o." + member(r.name);
    for (const Field* f : reg2hw_fields(m, r)) {
      o << "  assign " << base << "." << member(f->name) << " = ";
      if (f->access == "rw") {
        o << member(r.name) << "_" << member(f->name) << "_q;\n";
      } else {
        o << "wdata[" << f->lsb << " +: " << f->width << "];\n";
      }
    }
    if (has_we(m, r)) o << "  assign " << base << ".we = we_" << member(r.name) << ";\n";
    if (has_re(r)) o << "  assign " << base << ".re = re_" << member(r.name) << ";\n";
  }

  for (const Port& p : m.ports) {
    o << "  assign reg2hw_o." << p.name << ".re    = rd_sample & rd_in_" << p.name << ";\n"
      << "  assign reg2hw_o." << p.name << ".index = " << p.name << "_index;\n";
  }

  // Interrupt.
  if (!m.interrupts.state.empty()) {
    const Register& st = m.reg(m.interrupts.state);
    const Register& en = m.reg(m.interrupts.enable);
    std::string now, next;
    for (size_t i = 0; i < st.fields.size(); ++i) {
      const std::string a = member(st.name) + "_" + member(st.fields[i].name);
      const std::string b = member(en.name) + "_" + member(en.fields[i].name);
      now += std::string(i ? " | " : "") + "(|(" + a + "_q & " + b + "_q))";
      next += std::string(i ? " | " : "") + "(|(" + a + "_d & " + b + "_d))";
    }
    o << "\n  // Interrupt.\n  assign irq_o      = " << now << ";\n"
      << "  assign irq_rise_o = ~irq_o & (" << next << ");\n";
  } else {
    o << "\n  assign irq_o      = 1'b0;\n  assign irq_rise_o = 1'b0;\n";
  }

  // Read multiplexer.
  o << "\n  // Read multiplexer: AND-OR over the one-hot word select, formed on the\n"
    << "  // sample edge only.\n"
    << "  logic [31:0] rd_value;\n  always_comb begin\n    rd_value = 32'd0;\n"
    << "    if (rd_sample) begin\n";
  for (size_t e = 0; e < ws.size(); ++e) {
    const Register& r = *ws[e].reg;
    std::string word;
    uint32_t constant = 0;
    for (const Field& f : r.fields) {
      if (f.access == "ro" && f.constant) constant |= f.reset << f.lsb;
    }
    if (constant != 0) word = sv_hex32(constant);
    for (const Field& f : r.fields) {
      std::string v;
      if (stored(f)) {
        v = member(r.name) + "_" + member(f.name) + "_q";
      } else if (f.hw_input() && !r.external && r.port.empty()) {
        v = "hw2reg_i." + member(r.name) + "." + member(f.name) +
            (r.count > 1 ? "[" + std::to_string(ws[e].index) + "]" : "");
      } else {
        continue;
      }
      word += std::string(word.empty() ? "" : " | ") + "(32'(" + v + ") << " +
              std::to_string(f.lsb) + ")";
    }
    if (word.empty()) continue;  // reads 0 (write-only or external)
    o << "      rd_value = rd_value | ({32{rd_sel_q[" << e << "]}} & (" << word << "));\n";
  }
  o << "    end\n  end\n\n";

  // Channels.
  o << "  // AXI4-Lite channels.\n"
    << "  always_ff @(posedge clk_i) begin\n    if (!rst_ni) begin\n"
    << "      awready_q  <= 1'b0;\n      bvalid_q   <= 1'b0;\n      bresp_q    <= RespOkay;\n"
    << "      arready_q  <= 1'b1;\n      rvalid_q   <= 1'b0;\n      rdata_q    <= '0;\n"
    << "      rresp_q    <= RespOkay;\n      rd_stage_q <= 2'd0;\n      rd_sel_q   <= '0;\n"
    << "      rd_data_q  <= '0;\n      rd_resp_q  <= RespOkay;\n";
  if (!ext.empty()) o << "      rd_ext_q   <= '0;\n";
  if (!m.ports.empty()) o << "      rd_port_q  <= '0;\n";
  o << "    end else begin\n"
    << "      // Write: AW and W are taken together, one write at a time.\n"
    << "      if (aw_hs) begin\n        awready_q <= 1'b0;\n        bvalid_q  <= 1'b1;\n"
    << "        bresp_q   <= wr_err ? RespSlvErr : RespOkay;\n"
    << "      end else if (!awready_q && !bvalid_q && s_axil_awvalid_i && s_axil_wvalid_i) begin\n"
    << "        awready_q <= 1'b1;\n      end\n"
    << "      if (b_hs) begin\n        bvalid_q <= 1'b0;\n        bresp_q  <= RespOkay;\n      "
       "end\n\n"
    << "      // Read: one in flight, sample on the edge after AR, respond on the next.\n"
    << "      if (rd_sample) begin\n        rd_data_q  <= rd_value;\n"
    << "        rd_resp_q  <= (|rd_sel_q) ? RespOkay : RespSlvErr;\n";
  if (!ext.empty()) {
    o << "        rd_ext_q   <= {";
    for (size_t k = ext.size(); k-- > 0;) {
      o << "rd_sel_q[" << ext[k] << "]" << (k ? ", " : "");
    }
    o << "};\n";
  }
  if (!m.ports.empty()) {
    o << "        rd_port_q  <= {";
    for (size_t k = m.ports.size(); k-- > 0;) {
      o << "rd_in_" << m.ports[k].name << (k ? ", " : "");
    }
    o << "};\n";
  }
  o << "        rd_stage_q <= 2'd2;\n      end else if (rd_stage_q == 2'd2) begin\n"
    << "        rvalid_q   <= 1'b1;\n"
    << "        rdata_q    <= rd_data_q";
  for (size_t k = 0; k < ext.size(); ++k) {
    const Register& r = *ws[ext[k]].reg;
    const Field& f = r.fields[0];
    o << "\n                    | ({32{rd_ext_q[" << k << "]}} & (32'(hw2reg_i." << member(r.name)
      << "." << member(f.name) << ") << " << f.lsb << "))";
  }
  for (size_t k = 0; k < m.ports.size(); ++k) {
    o << "\n                    | ({32{rd_port_q[" << k << "]}} & hw2reg_i." << m.ports[k].name
      << ".data)";
  }
  o << ";\n";
  o << "        rresp_q    <= rd_resp_q;\n        rd_stage_q <= 2'd3;\n      end\n"
    << "      if (r_hs) begin\n        rvalid_q   <= 1'b0;\n        rdata_q    <= '0;\n"
    << "        rresp_q    <= RespOkay;\n        arready_q  <= 1'b1;\n"
    << "        rd_stage_q <= 2'd0;\n      end\n"
    << "      if (ar_hs) begin\n        arready_q  <= 1'b0;\n        rd_sel_q   <= ar_match;\n"
    << "        rd_stage_q <= 2'd1;\n      end\n    end\n  end\n\n"
    << "  assign s_axil_awready_o = awready_q;\n  assign s_axil_wready_o  = awready_q;\n"
    << "  assign s_axil_bvalid_o  = bvalid_q;\n  assign s_axil_bresp_o   = bresp_q;\n"
    << "  assign s_axil_arready_o = arready_q;\n  assign s_axil_rvalid_o  = rvalid_q;\n"
    << "  assign s_axil_rdata_o   = rdata_q;\n  assign s_axil_rresp_o   = rresp_q;\n\n"
    << "  // Address bits above the window and write data bits of no field.\n"
    << "  logic unused;\n"
    << "  assign unused = ^{s_axil_awaddr_i[31:AddrBits], s_axil_araddr_i[31:AddrBits], wdata};\n\n"
    << "endmodule\n";
  return o.str();
}

namespace {

// A member of a packed struct port: its C++ expression, LSB and width.
struct Bits {
  std::string expr;
  uint32_t lsb;
  uint32_t width;
  bool flag;  // a bool in C++ (we, re)
};

// SV packed layout: the first member is the most significant.
std::vector<Bits> reg2hw_layout(const RegMap& m) {
  std::vector<Bits> out;
  uint32_t lsb = 0;
  const std::vector<Word> ws = words(m);
  for (auto p = m.ports.rbegin(); p != m.ports.rend(); ++p) {  // after the registers
    out.push_back({p->name + ".re", lsb++, 1, true});
    const uint32_t ib = index_bits(port_words(ws, p->name).size());
    out.push_back({p->name + ".index", lsb, ib, false});
    lsb += ib;
  }
  for (auto r = m.registers.rbegin(); r != m.registers.rend(); ++r) {
    if (!in_reg2hw(m, *r)) continue;
    const std::string base = member(r->name) + ".";
    if (has_re(*r)) out.push_back({base + "re", lsb++, 1, true});
    if (has_we(m, *r)) out.push_back({base + "we", lsb++, 1, true});
    const auto fields = reg2hw_fields(m, *r);
    for (auto f = fields.rbegin(); f != fields.rend(); ++f) {
      out.push_back({base + member((*f)->name), lsb, (*f)->width, false});
      lsb += (*f)->width;
    }
  }
  return out;
}
std::vector<Bits> hw2reg_layout(const RegMap& m) {
  std::vector<Bits> out;
  uint32_t lsb = 0;
  for (auto p = m.ports.rbegin(); p != m.ports.rend(); ++p) {  // after the registers
    if (p->wait) out.push_back({p->name + ".ready", lsb++, 1, true});
    out.push_back({p->name + ".data", lsb, 32, false});
    lsb += 32;
  }
  for (auto r = m.registers.rbegin(); r != m.registers.rend(); ++r) {
    const auto fields = hw2reg_fields(*r);
    for (auto f = fields.rbegin(); f != fields.rend(); ++f) {
      const std::string e = member(r->name) + "." + member((*f)->name);
      for (uint32_t i = 0; i < r->count; ++i) {
        out.push_back(
            {r->count > 1 ? e + "[" + std::to_string(i) + "]" : e, lsb, (*f)->width, false});
        lsb += (*f)->width;
      }
    }
  }
  return out;
}
uint32_t total_bits(const std::vector<Bits>& layout) {
  uint32_t n = 0;
  for (const Bits& b : layout) n = std::max(n, b.lsb + b.width);
  return n;
}

}  // namespace

// ---- C++: the cycle model of the register block.
std::string cpp_regblock(const RegMap& m) {
  const std::vector<Word> ws = words(m);
  std::ostringstream o;
  o << "// Generated by tools/regmap_gen from rtl_model/regmap.json. Do not edit.\n"
    << "// The register block of the device as a cycle model: the twin of the\n"
    << "// generated " << m.name << "_regblock.sv (behaviour: tools/regblock_emit.cpp,\n"
    << "// docs/registers.md).\n"
    << "#pragma once\n\n#include <array>\n#include <cstdint>\n\n"
    << "#include \"" << m.name << "/regs.hpp\"\n#include \"stream/axi_lite.hpp\"\n\n"
    << "namespace " << m.name << "::stream {\n\n";
  if (m.name != "ceilnav") {
    o << "using ::ceilnav::stream::AxiLiteIn;\nusing ::ceilnav::stream::AxiLiteOut;\n\n";
  }

  // Reg2Hw / Hw2Reg.
  o << "// Register block -> design: stored rw fields (the values before the edge\n"
    << "// until commit()), the write data of this edge (wo fields, valid with we)\n"
    << "// and the strobes of this edge.\nstruct Reg2Hw {\n";
  for (const Register& r : m.registers) {
    if (!in_reg2hw(m, r)) continue;
    o << "  struct {\n";
    for (const Field* f : reg2hw_fields(m, r)) {
      o << "    uint32_t " << member(f->name) << " = " << f->reset << "u;  // " << f->access
        << "\n";
    }
    if (has_we(m, r)) o << "    bool we = false;\n";
    if (has_re(r)) o << "    bool re = false;\n";
    o << "  } " << member(r.name) << ";\n";
  }
  for (const Port& p : m.ports) {
    o << "  struct {\n    uint32_t index = 0;  // word of the port (with re)\n"
      << "    bool re = false;\n  } " << p.name << ";\n";
  }
  o << "};\n\n"
    << "// Design -> register block: ro values and w1c set bits, as they are before\n"
    << "// the edge (an external register's value: one edge after its read strobe).\n"
    << "struct Hw2Reg {\n";
  for (const Register& r : m.registers) {
    const auto fields = hw2reg_fields(r);
    if (fields.empty()) continue;
    o << "  struct {\n";
    for (const Field* f : fields) {
      if (r.count > 1) {
        o << "    std::array<uint32_t, " << r.count << "> " << member(f->name) << "{};\n";
      } else {
        o << "    uint32_t " << member(f->name) << " = 0;\n";
      }
    }
    o << "  } " << member(r.name) << ";\n";
  }
  for (const Port& p : m.ports) {
    o << "  struct {\n    uint32_t data = 0;  // the word, one edge after re\n";
    if (p.wait) o << "    bool ready = false;  // false: hold a read of the port\n";
    o << "  } " << p.name << ";\n";
  }
  o << "};\n\n";

  // Class.
  o << "class RegBlock {\n public:\n"
    << "  static constexpr int kWords = " << ws.size() << ";\n\n"
    << "  explicit RegBlock(const regs::Config& config) : config_(config) { reset(); }\n\n"
    << "  void reset() {\n    reg2hw_ = Reg2Hw{};\n";
  for (const Register& r : m.registers) {
    for (const Field& f : r.fields) {
      if (stored(f)) {
        o << "    " << member(r.name) << "_" << member(f.name) << "_q_ = " << f.reset << "u;\n";
      }
    }
  }
  o << "    out_ = AxiLiteOut{};\n    out_.arready = true;\n    rd_stage_q_ = 0;\n"
    << "    rd_word_q_ = -1;\n    rd_data_q_ = 0;\n    rd_resp_q_ = regs::kRespOkay;\n"
    << "    rd_ext_q_ = -1;\n    rd_port_q_ = -1;\n    sampling_ = false;\n    wr_word_ = -1;\n    "
       "wr_err_ = false;\n    irq_rise_ = false;\n  "
       "}\n\n"
    << "  // First half of an edge, from the bus inputs and the state before it: the\n"
    << "  // write decode and the strobes and write data of reg2hw(). Of `hw` only the\n"
    << "  // ports' ready bits are used (they decide whether a read is held).\n"
    << "  void begin_edge(const AxiLiteIn& in, [[maybe_unused]] const Hw2Reg& hw) {\n";
  for (const Register& r : m.registers) {
    if (has_we(m, r)) o << "    reg2hw_." << member(r.name) << ".we = false;\n";
    if (has_re(r)) o << "    reg2hw_." << member(r.name) << ".re = false;\n";
  }
  o << "    aw_hs_ = out_.awready && in.awvalid && in.wvalid;  // wready == awready\n"
    << "    wr_word_ = -1;\n    wr_err_ = false;\n    if (aw_hs_) {\n"
    << "      const int w = word_of(in.awaddr);\n"
    << "      wr_err_ = w < 0 || !writable(w) || in.wstrb != 0xF;\n"
    << "      if (!wr_err_) wr_word_ = w;\n    }\n"
    << "    // wo fields: the write data bus, whatever the strobe (as the SV).\n";
  for (const Register& r : m.registers) {
    for (const Field* f : reg2hw_fields(m, r)) {
      if (f->access == "wo") {
        o << "    reg2hw_." << member(r.name) << "." << member(f->name)
          << " = regs::" << lower(r.name) << "::k" << camel(f->name) << ".get(in.wdata);\n";
      }
    }
  }
  o << "    switch (wr_word_) {\n";
  for (size_t e = 0; e < ws.size(); ++e) {
    const Register& r = *ws[e].reg;
    if (!has_we(m, r)) continue;
    o << "      case " << e << ":\n"
      << "        reg2hw_." << member(r.name) << ".we = true;\n        break;\n";
  }
  o << "      default:\n        break;\n    }\n"
    << "    // Ports: the index of the word in flight; a port that is not ready holds it.\n"
    << "    sampling_ = rd_stage_q_ == 1;\n";
  for (const Port& p : m.ports) {
    o << "    {\n      const int k = port_index(" << &p - &m.ports[0] << ", rd_word_q_);\n"
      << "      reg2hw_." << p.name << ".index = k >= 0 ? static_cast<uint32_t>(k) : 0u;\n";
    if (p.wait) o << "      if (k >= 0 && !hw." << p.name << ".ready) sampling_ = false;\n";
    o << "    }\n";
  }
  for (const Port& p : m.ports) {
    o << "    reg2hw_." << p.name << ".re = sampling_ && port_index(" << &p - &m.ports[0]
      << ", rd_word_q_) >= 0;\n";
  }
  o << "    if (sampling_) {\n      switch (rd_word_q_) {\n";
  for (size_t e = 0; e < ws.size(); ++e) {
    const Register& r = *ws[e].reg;
    if (!has_re(r)) continue;
    o << "        case " << e << ":\n          reg2hw_." << member(r.name)
      << ".re = true;\n          break;\n";
  }
  o << "        default:\n          break;\n      }\n    }\n  }\n\n"
    << "  // This edge samples a read: its value comes from the hardware inputs,\n"
    << "  // which the caller fills before commit().\n"
    << "  bool read_sampling() const { return sampling_; }\n\n"
    << "  // The edge itself (after begin_edge() with the same inputs).\n"
    << "  void commit(const AxiLiteIn& in, const Hw2Reg& hw) {\n"
    << "    const uint32_t wdata = in.wdata;\n"
    << "    const bool b_hs = out_.bvalid && in.bready;\n"
    << "    const bool ar_hs = out_.arready && in.arvalid;\n"
    << "    const bool r_hs = out_.rvalid && in.rready;\n"
    << "    uint32_t rd_value = 0;\n"
    << "    if (sampling_ && rd_word_q_ >= 0) rd_value = read_word(rd_word_q_, hw);\n\n";
  // Stored fields: next values.
  for (const Register& r : m.registers) {
    for (const Field& f : r.fields) {
      if (!stored(f)) continue;
      const std::string s = member(r.name) + "_" + member(f.name);
      const std::string get = "regs::" + lower(r.name) + "::k" + camel(f.name) + ".get(wdata)";
      const std::string fmask =
          std::to_string(f.width >= 32 ? 0xFFFFFFFFu : (1u << f.width) - 1u) + "u";
      if (f.access == "rw") {
        o << "    uint32_t " << s << "_d = " << s << "_q_;\n"
          << "    if (reg2hw_we(" << word_of_name(m, r) << ")) {\n      " << s << "_d = " << get
          << ";\n    }";
        for (const auto& [src, read] : incrementers(m, r, f)) {
          o << " else if (reg2hw_." << member(src->name) << (read ? ".re" : ".we") << ") {\n      "
            << s << "_d = (" << s << "_q_ + 1u) & " << fmask << ";\n    }";
        }
        o << "\n";
      } else {
        std::string set = "hw." + member(r.name) + "." + member(f.name);
        if (r.name == m.interrupts.state) {
          set += " | (reg2hw_we(" + word_of_name(m, m.reg(m.interrupts.test)) +
                 ") ? regs::" + lower(m.interrupts.test) + "::k" + camel(f.name) +
                 ".get(wdata) : 0u)";
        }
        o << "    const uint32_t " << s << "_d = (" << s << "_q_ & ~(reg2hw_we("
          << word_of_name(m, r) << ") ? " << get << " : 0u)) | ((" << set << ") & " << fmask
          << ");\n";
      }
    }
  }
  // irq rise.
  if (!m.interrupts.state.empty()) {
    const Register& st = m.reg(m.interrupts.state);
    const Register& en = m.reg(m.interrupts.enable);
    std::string next;
    for (size_t i = 0; i < st.fields.size(); ++i) {
      const std::string a = member(st.name) + "_" + member(st.fields[i].name);
      const std::string b = member(en.name) + "_" + member(en.fields[i].name);
      next += std::string(i ? " || " : "") + "(" + a + "_d & " + b + "_d) != 0u";
    }
    o << "    irq_rise_ = !irq() && (" << next << ");\n";
  }
  for (const Register& r : m.registers) {
    for (const Field& f : r.fields) {
      if (!stored(f)) continue;
      const std::string s = member(r.name) + "_" + member(f.name);
      o << "    " << s << "_q_ = " << s << "_d;\n";
      if (f.access == "rw" && !is_interrupt(m, r)) {
        o << "    reg2hw_." << member(r.name) << "." << member(f.name) << " = " << s << "_d;\n";
      }
    }
  }
  o << "\n    // Write channel: AW and W are taken together.\n"
    << "    if (aw_hs_) {\n      out_.awready = out_.wready = false;\n      out_.bvalid = true;\n"
    << "      out_.bresp = wr_err_ ? regs::kRespSlvErr : regs::kRespOkay;\n"
    << "    } else if (!out_.awready && !out_.bvalid && in.awvalid && in.wvalid) {\n"
    << "      out_.awready = out_.wready = true;\n    }\n"
    << "    if (b_hs) {\n      out_.bvalid = false;\n      out_.bresp = regs::kRespOkay;\n    }\n"
    << "    // Read channel: one read in flight.\n"
    << "    if (sampling_) {\n      rd_data_q_ = rd_value;\n"
    << "      rd_resp_q_ = rd_word_q_ >= 0 ? regs::kRespOkay : regs::kRespSlvErr;\n"
    << "      rd_ext_q_ = rd_word_q_ >= 0 && external(rd_word_q_) ? rd_word_q_ : -1;\n"
    << "      rd_port_q_ = port_of(rd_word_q_);\n"
    << "      rd_stage_q_ = 2;\n    } else if (rd_stage_q_ == 2) {\n      out_.rvalid = true;\n"
    << "      out_.rdata = rd_ext_q_ >= 0    ? read_external(rd_ext_q_, hw)\n"
    << "                   : rd_port_q_ >= 0 ? port_data(rd_port_q_, hw)\n"
    << "                                     : rd_data_q_;\n"
    << "      out_.rresp = rd_resp_q_;\n      rd_stage_q_ = 3;\n    }\n"
    << "    if (r_hs) {\n      out_.rvalid = false;\n      out_.rdata = 0;\n"
    << "      out_.rresp = regs::kRespOkay;\n      out_.arready = true;\n      rd_stage_q_ = 0;\n  "
       "  }\n"
    << "    if (ar_hs) {\n      out_.arready = false;\n      rd_word_q_ = word_of(in.araddr);\n"
    << "      rd_stage_q_ = 1;\n    }\n  }\n\n"
    << "  const Reg2Hw& reg2hw() const { return reg2hw_; }\n"
    << "  const AxiLiteOut& out() const { return out_; }\n";
  if (!m.interrupts.state.empty()) {
    const Register& st = m.reg(m.interrupts.state);
    const Register& en = m.reg(m.interrupts.enable);
    std::string now;
    for (size_t i = 0; i < st.fields.size(); ++i) {
      now += std::string(i ? " || " : "") + "(" + member(st.name) + "_" +
             member(st.fields[i].name) + "_q_ & " + member(en.name) + "_" +
             member(en.fields[i].name) + "_q_) != 0u";
    }
    o << "  // |(state & enable), registered.\n  bool irq() const { return " << now << "; }\n";
  } else {
    o << "  bool irq() const { return false; }\n";
  }
  o << "  // irq() rose on the last commit().\n  bool irq_rise() const { return irq_rise_; }\n"
    << "  // The word written on this edge (after begin_edge()), -1 if none.\n"
    << "  int written_word() const { return wr_word_; }\n"
    << "  const regs::Config& config() const { return config_; }\n\n"
    << "  // The present word at byte address `addr`, or -1.\n"
    << "  int word_of(uint32_t addr) const {\n    int w = -1;\n"
    << "    switch (addr & regs::kAddrMask) {\n";
  for (size_t e = 0; e < ws.size(); ++e) {
    o << "      case 0x" << hex(ws[e].offset, 3) << "u:\n        w = " << e
      << ";\n        break;\n";
  }
  o << "      default:\n        return -1;\n    }\n    return present(w) ? w : -1;\n  }\n\n"
    << " private:\n"
    << "  bool reg2hw_we(int word) const { return wr_word_ == word; }\n"
    << "  bool present(int word) const {\n    switch (word) {\n";
  for (size_t e = 0; e < ws.size(); ++e) {
    if (ws[e].reg->block.empty()) continue;
    o << "      case " << e << ":\n        return config_.has(regs::Block::k"
      << camel(ws[e].reg->block) << ");\n";
  }
  o << "      default:\n        return true;\n    }\n  }\n"
    << "  static bool writable(int word) {\n    switch (word) {\n";
  for (size_t e = 0; e < ws.size(); ++e) {
    if (writable(*ws[e].reg)) o << "      case " << e << ":\n";
  }
  o << "        return true;\n      default:\n        return false;\n    }\n  }\n"
    << "  // Index of `word` in port `port`, or -1.\n"
    << "  static int port_index([[maybe_unused]] int port, [[maybe_unused]] int word) {\n";
  for (size_t k = 0; k < m.ports.size(); ++k) {
    const auto pw = port_words(ws, m.ports[k].name);
    o << "    if (port == " << k << ") {\n      switch (word) {\n";
    for (size_t i = 0; i < pw.size(); ++i) {
      o << "        case " << pw[i] << ":\n          return " << i << ";\n";
    }
    o << "        default:\n          return -1;\n      }\n    }\n";
  }
  o << "    return -1;\n  }\n"
    << "  // The port `word` belongs to, or -1.\n"
    << "  static int port_of([[maybe_unused]] int word) {\n";
  for (size_t k = 0; k < m.ports.size(); ++k) {
    o << "    if (port_index(" << k << ", word) >= 0) return " << k << ";\n";
  }
  o << "    return -1;\n  }\n"
    << "  static uint32_t port_data([[maybe_unused]] int port, [[maybe_unused]] const Hw2Reg& hw) "
       "{\n";
  for (size_t k = 0; k < m.ports.size(); ++k) {
    o << "    if (port == " << k << ") return hw." << m.ports[k].name << ".data;\n";
  }
  o << "    return 0;\n  }\n"
    << "  static bool external(int word) {\n    switch (word) {\n";
  bool any_ext = false;
  for (size_t e = 0; e < ws.size(); ++e) {
    if (ws[e].reg->external) {
      o << "      case " << e << ":\n";
      any_ext = true;
    }
  }
  if (any_ext) o << "        return true;\n";
  o << "      default:\n        return false;\n    }\n  }\n"
    << "  static uint32_t read_external([[maybe_unused]] int word, [[maybe_unused]] const Hw2Reg& "
       "hw) {\n"
    << "    switch (word) {\n";
  for (size_t e = 0; e < ws.size(); ++e) {
    const Register& r = *ws[e].reg;
    if (!r.external) continue;
    o << "      case " << e << ":\n        return regs::" << lower(r.name) << "::k"
      << camel(r.fields[0].name) << ".put(hw." << member(r.name) << "." << member(r.fields[0].name)
      << ");\n";
  }
  o << "      default:\n        return 0;\n    }\n  }\n"
    << "  uint32_t read_word(int word, [[maybe_unused]] const Hw2Reg& hw) const {\n"
    << "    switch (word) {\n";
  for (size_t e = 0; e < ws.size(); ++e) {
    const Register& r = *ws[e].reg;
    std::string v;
    uint32_t constant = 0;
    for (const Field& f : r.fields) {
      if (f.access == "ro" && f.constant) constant |= f.reset << f.lsb;
    }
    if (constant != 0) v = "0x" + hex(constant, 8) + "u";
    for (const Field& f : r.fields) {
      std::string x;
      if (stored(f)) {
        x = member(r.name) + "_" + member(f.name) + "_q_";
      } else if (f.hw_input() && !r.external && r.port.empty()) {
        x = "hw." + member(r.name) + "." + member(f.name) +
            (r.count > 1 ? "[" + std::to_string(ws[e].index) + "]" : "");
      } else {
        continue;
      }
      const std::string put = "regs::" + lower(r.name) + "::k" + camel(f.name) + ".put(" + x + ")";
      v += std::string(v.empty() ? "" : " | ") + put;
    }
    if (v.empty()) continue;
    o << "      case " << e << ":\n        return " << v << ";\n";
  }
  o << "      default:\n        return 0;  // write-only, external or no register\n    }\n  }\n\n"
    << "  regs::Config config_;\n  Reg2Hw reg2hw_{};\n";
  for (const Register& r : m.registers) {
    for (const Field& f : r.fields) {
      if (stored(f)) o << "  uint32_t " << member(r.name) << "_" << member(f.name) << "_q_ = 0;\n";
    }
  }
  o << "  AxiLiteOut out_{};\n  bool aw_hs_ = false;\n  bool wr_err_ = false;\n"
    << "  int wr_word_ = -1;\n  uint8_t rd_stage_q_ = 0;  // 0 idle, 1 sample, 2 respond, 3 "
       "rvalid\n"
    << "  int rd_word_q_ = -1;\n  uint32_t rd_data_q_ = 0;\n  uint8_t rd_resp_q_ = 0;\n"
    << "  int rd_ext_q_ = -1;\n  int rd_port_q_ = -1;\n  bool sampling_ = false;\n"
    << "  bool irq_rise_ = false;\n};\n\n"
    << "// The packed struct ports of the SV block as 32-bit words (word 0 = bits\n"
    << "// 31:0), for harnesses that drive both: first member = most significant.\n";
  const auto h2r = hw2reg_layout(m);
  const auto r2h = reg2hw_layout(m);
  o << "inline constexpr uint32_t kHw2RegBits = " << total_bits(h2r) << ";\n"
    << "inline constexpr uint32_t kReg2HwBits = " << total_bits(r2h) << ";\n\n"
    << "namespace detail {\n"
    << "inline void put_bits(uint32_t* words, uint32_t lsb, uint32_t width, uint32_t v) {\n"
    << "  for (uint32_t b = 0; b < width; ++b) {\n"
    << "    if ((v >> b) & 1u) words[(lsb + b) / 32] |= 1u << ((lsb + b) % 32);\n  }\n}\n"
    << "inline uint32_t get_bits(const uint32_t* words, uint32_t lsb, uint32_t width) {\n"
    << "  uint32_t v = 0;\n  for (uint32_t b = 0; b < width; ++b) {\n"
    << "    v |= ((words[(lsb + b) / 32] >> ((lsb + b) % 32)) & 1u) << b;\n  }\n"
    << "  return v;\n}\n}  // namespace detail\n\n";
  const auto emit = [&o](const char* type, const char* what, const std::vector<Bits>& layout,
                         const char* bits) {
    o << "inline void pack_" << what << "(const " << type << "& s, uint32_t* words) {\n"
      << "  for (uint32_t i = 0; i < (" << bits << " + 31) / 32; ++i) words[i] = 0;\n";
    for (const Bits& b : layout) {
      o << "  detail::put_bits(words, " << b.lsb << ", " << b.width << ", "
        << (b.flag ? "s." + b.expr + " ? 1u : 0u" : "s." + b.expr) << ");\n";
    }
    o << "}\ninline " << type << " unpack_" << what << "(const uint32_t* words) {\n  " << type
      << " s;\n";
    for (const Bits& b : layout) {
      o << "  s." << b.expr << " = detail::get_bits(words, " << b.lsb << ", " << b.width << ")"
        << (b.flag ? " != 0" : "") << ";\n";
    }
    o << "  return s;\n}\n\n";
  };
  emit("Hw2Reg", "hw2reg", h2r, "kHw2RegBits");
  emit("Reg2Hw", "reg2hw", r2h, "kReg2HwBits");
  o << "}  // namespace " << m.name << "::stream\n";
  return o.str();
}

}  // namespace regmap
