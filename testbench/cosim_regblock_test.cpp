// The register block generator on its own: the SV rbtest_regblock and the C++
// rbtest::stream::RegBlock, both generated from testbench/regblock_test_map.json
// (a map that uses every feature: rw/wo/w1c/ro fields, constants, parameters,
// arrays, external registers, read and write effects, multi-bit interrupts, an
// optional block), driven with the same random bus and hardware inputs, compared
// on every output bit every cycle: the AXI4-Lite outputs, the whole reg2hw
// struct, irq_o and irq_rise_o. The `ram` port is not ready 30 % of the time
// (reads of it are held). The bus is raw random (valids and readys
// toggling, addresses in and out of the map, partial strobes): both must agree
// whatever the master does. Built twice: with and without the optional block.
#include <array>
#include <cstdint>
#include <vector>

#include "rbtest/regblock.hpp"
#include "stream/axi_lite.hpp"
#include "testbench/cosim_common.hpp"
#include "testbench/ports.hpp"

#if RBTEST_HAS_EXTRA
#include "Vrbtest_regblock.h"
using Dut = Vrbtest_regblock;
#else
#include "Vrbtest_regblock_small.h"
using Dut = Vrbtest_regblock_small;
#endif

namespace {

using ceilnav::stream::AxiLiteIn;
using ceilnav::testbench::check_s_axil;
using ceilnav::testbench::Cosim;
using ceilnav::testbench::drive_s_axil;
using ceilnav::testbench::Rng;
using rbtest::stream::Hw2Reg;
using rbtest::stream::kHw2RegBits;
using rbtest::stream::kReg2HwBits;
using rbtest::stream::Reg2Hw;
using rbtest::stream::RegBlock;

constexpr uint32_t kHw2RegWords = (kHw2RegBits + 31) / 32;
constexpr uint32_t kReg2HwWords = (kReg2HwBits + 31) / 32;

#if RBTEST_HAS_EXTRA
constexpr const rbtest::regs::Config& kConfig = rbtest::regs::kConfigBig;
#else
constexpr const rbtest::regs::Config& kConfig = rbtest::regs::kConfigSmall;
#endif

// A Verilator port of any width as 32-bit words.
template <class Port>
void to_words(const Port& port, uint32_t* words, uint32_t count) {
  if constexpr (std::is_integral_v<Port>) {
    for (uint32_t i = 0; i < count; ++i) {
      words[i] = static_cast<uint32_t>(static_cast<uint64_t>(port) >> (32 * i));
    }
  } else {
    for (uint32_t i = 0; i < count; ++i) words[i] = port[i];
  }
}
template <class Port>
void from_words(Port& port, const uint32_t* words, uint32_t count) {
  if constexpr (std::is_integral_v<Port>) {
    uint64_t v = 0;
    for (uint32_t i = 0; i < count; ++i) v |= static_cast<uint64_t>(words[i]) << (32 * i);
    port = static_cast<Port>(v);
  } else {
    for (uint32_t i = 0; i < count; ++i) port[i] = words[i];
  }
}

// Random hardware inputs: every bit random, set pulses rare.
Hw2Reg random_hw(Rng& rng) {
  std::array<uint32_t, kHw2RegWords> w{};
  for (uint32_t& x : w) x = static_cast<uint32_t>(rng.engine()());
  Hw2Reg hw = rbtest::stream::unpack_hw2reg(w.data());
  if (!rng.chance(0.1)) hw.intr_state = {};
  if (!rng.chance(0.1)) hw.cause = {};
  hw.ram.ready = rng.chance(0.7);
  return hw;
}

uint32_t random_address(Rng& rng) {
  static const std::vector<uint32_t> kOffsets = [] {
    std::vector<uint32_t> v;
    for (const auto& r : rbtest::regs::kRegisters) v.push_back(r.offset);
    return v;
  }();
  const int pick = static_cast<int>(rng.uniform(0, 9));
  if (pick < 7) return kOffsets[rng.index(kOffsets.size())];
  if (pick < 8) return static_cast<uint32_t>(rng.uniform(0, 0xFF)) & ~3u;  // any word
  if (pick < 9) return static_cast<uint32_t>(rng.uniform(0, 0xFF));        // maybe misaligned
  return static_cast<uint32_t>(rng.engine()());                            // high bits too
}

void run(uint64_t seed, uint64_t cycles) {
  Cosim<Dut> sim(kConfig.name, seed);
  Dut& dut = sim.dut();
  RegBlock model(kConfig);
  Rng rng(seed);
  AxiLiteIn in;
  uint64_t okay_reads = 0, okay_writes = 0, irq_rises = 0, ext_reads = 0, store_reads = 0;
  for (uint64_t c = 0; c < cycles && !sim.failed(); ++c) {
    if (rng.chance(0.0005)) {
      sim.reset_cycle();
      model.reset();
    }
    // Raw random master: sticky valids with random drops, random readys.
    if (!in.awvalid || rng.chance(0.2)) {
      in.awvalid = rng.chance(0.3);
      in.awaddr = random_address(rng);
      in.wvalid = rng.chance(0.8) ? in.awvalid : rng.chance(0.5);
      in.wdata = static_cast<uint32_t>(rng.engine()());
      in.wstrb = rng.chance(0.9) ? 0xF : static_cast<uint8_t>(rng.uniform(0, 15));
    }
    if (!in.arvalid || rng.chance(0.2)) {
      in.arvalid = rng.chance(0.4);
      in.araddr = random_address(rng);
    }
    in.bready = rng.chance(0.7);
    in.rready = rng.chance(0.7);
    const Hw2Reg hw = random_hw(rng);

    drive_s_axil(dut, in);
    std::array<uint32_t, kHw2RegWords> hw_words{};
    rbtest::stream::pack_hw2reg(hw, hw_words.data());
    from_words(dut.hw2reg_i, hw_words.data(), kHw2RegWords);
    dut.eval();

    // Before the edge: the strobes and write data of this edge, the stored values.
    model.begin_edge(in, hw);
    std::array<uint32_t, kReg2HwWords> rtl_words{}, model_words{};
    to_words(dut.reg2hw_o, rtl_words.data(), kReg2HwWords);
    rbtest::stream::pack_reg2hw(model.reg2hw(), model_words.data());
    for (uint32_t i = 0; i < kReg2HwWords; ++i) {
      sim.check("reg2hw_o (32-bit word)", rtl_words[i], model_words[i]);
    }
    sim.check("irq_o", dut.irq_o, model.irq());
    const bool rtl_rise = dut.irq_rise_o;

    sim.edge();
    model.commit(in, hw);
    const auto& out = model.out();
    sim.check("irq_rise_o", rtl_rise, model.irq_rise());
    check_s_axil(sim, dut, out);
    if (out.rvalid && in.rready && out.rresp == 0) ++okay_reads;
    if (out.bvalid && in.bready && out.bresp == 0) ++okay_writes;
    if (model.irq_rise()) ++irq_rises;
    if (model.reg2hw().port.re) ++ext_reads;
    if (model.reg2hw().ram.re) ++store_reads;
  }
  std::printf(
      "[cosim] %s: %llu cycles, %llu checks, %llu OKAY reads, %llu OKAY writes, "
      "%llu irq rises, %llu PORT read strobes, %llu ram port reads\n",
      kConfig.name, static_cast<unsigned long long>(sim.cycle()),
      static_cast<unsigned long long>(sim.checks()), static_cast<unsigned long long>(okay_reads),
      static_cast<unsigned long long>(okay_writes), static_cast<unsigned long long>(irq_rises),
      static_cast<unsigned long long>(ext_reads), static_cast<unsigned long long>(store_reads));
  EXPECT_GT(okay_reads, 1000u);
  EXPECT_GT(okay_writes, 1000u);
  EXPECT_GT(irq_rises, 10u);
  EXPECT_GT(store_reads, 100u);
}

TEST(RegblockCosim, EveryOutputBitEveryCycle) {
  run(ceilnav::testbench::cosim_seed(20261125), ceilnav::testbench::cosim_count(300000));
}

}  // namespace
