// The pipeline top: frame_check -> thresh_lut -> {histogram, moment_gen,
// class_moments, run_scanner, edge -> hough, orientation}, the shadow/active configuration, the
// double-buffered frame result registers and the frame_done interrupt source.
// See docs/blocks/pipeline.md.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "common/hough_params.hpp"
#include "common/pipeline_config.hpp"
#include "common/results.hpp"
#include "common/run_record.hpp"
#include "stream/beat.hpp"
#include "stream/class_moments.hpp"
#include "stream/edge.hpp"
#include "stream/frame_check.hpp"
#include "stream/histogram.hpp"
#include "stream/hough.hpp"
#include "stream/moment_gen.hpp"
#include "stream/orientation.hpp"
#include "stream/run_scanner.hpp"
#include "stream/thresh_lut.hpp"

namespace ceilnav::stream {

class Pipeline {
 public:
  // Pipeline registers between the EOF beat on s_axis_video and frame_done:
  // frame_check (1) + thresh_lut (1) + moment_gen combine (kCombineCycles).
  static constexpr int kEofToFrameDoneCycles = 2 + MomentGen::kCombineCycles;

  // has_class_moments = false is the RTL's HasClassMoments = 0: no
  // class_moments block, results().class_moments all zero; every other output
  // is the same as with true.
  // has_corridor = false is the RTL's HasCorridor = 0: no edge and no hough
  // block (their outputs read idle / 0). hough_shape: the hough block's
  // compile-time shape (the RTL's HoughLanes, HoughThetaStep, HoughRhoBits,
  // HoughAccBits); edge_fifo_depth: the edge FIFO (EdgeFifoDepth).
  // has_orientation = true is the RTL's HasOrientation = 1: the orientation
  // block on the LUT remap stream beside the edge block, with ori_bins bins
  // (OriBins); without it its outputs read idle / 0.
  explicit Pipeline(uint32_t run_fifo_depth = RunScanner::kDefaultFifoDepth,
                    bool has_class_moments = true, bool has_corridor = true,
                    const HoughShape& hough_shape = HoughShape{},
                    uint32_t edge_fifo_depth = EdgeDetector::kDefaultFifoDepth,
                    bool has_orientation = false, uint32_t ori_bins = Orientation::kDefaultBins);

  bool has_class_moments() const { return has_class_moments_; }
  bool has_corridor() const { return has_corridor_; }
  bool has_orientation() const { return has_orientation_; }

  // Synchronous active-low reset of every register (not of the LUT BRAM nor
  // of the shadow configuration, which the host owns).
  void reset();

  // Host: writes the shadow configuration, including all 256 LUT entries; the
  // whole of it becomes active at the next SOF beat on s_axis_video.
  void set_config(const PipelineConfig& cfg);
  const PipelineConfig& shadow_config() const { return shadow_; }

  // Host: the corridor blocks' configuration. `edge` is a shadow like the
  // PipelineConfig (it travels down the pipeline with the SOF and the edge
  // block latches it at the SOF pixel); `hough` drives the hough block's
  // configuration port directly (it samples it with a frame's first edge beat).
  void set_corridor_config(const EdgeConfig& edge, const HoughConfig& hough) {
    edge_shadow_ = edge;
    hough_cfg_ = hough;
  }
  const EdgeConfig& edge_shadow_config() const { return edge_shadow_; }
  // Host: the orientation block's configuration, a shadow like EDGE_CONTROL
  // (it travels with the SOF; the block latches it at the SOF pixel).
  void set_orientation_config(const OrientationConfig& ori) { ori_shadow_ = ori; }
  const OrientationConfig& orientation_shadow_config() const { return ori_shadow_; }
  const HoughConfig& hough_config() const { return hough_cfg_; }

  // One rising clock edge. s_axis_video_tready is always 1.
  void clock(const VideoBeat& s_axis_video, bool m_axis_runs_tready);
  // One rising clock edge with the histogram block's result read port
  // (histogram.sv hist_rd_en_i / hist_rd_bin_i) sampled on it too.
  // With the hough block's result read port (hough.sv rd_en_i / rd_index_i)
  // as well (ignored without the corridor blocks), and the orientation
  // block's (orientation.sv hist_rd_en_i / hist_rd_bin_i; ignored without it).
  void clock(const VideoBeat& s_axis_video, bool m_axis_runs_tready, bool hist_rd_en,
             uint8_t hist_rd_bin, bool hough_rd_en = false, uint32_t hough_rd_index = 0,
             bool ori_rd_en = false, uint8_t ori_rd_bin = 0);

  // Registered outputs.
  RunBeat m_axis_runs() const { return runs_.m_axis_runs(); }
  // One-cycle pulse, high in the cycle in which results() first shows the
  // new frame (the interrupt source: the register block latches it).
  bool frame_done() const { return frame_done_q_; }
  const FrameResults& results() const { return results_q_; }
  // Registered output of the histogram read port: after an edge that sampled
  // a read of bin b, bin b of the histogram block's result bank as it was
  // before that edge, else 0. The result bank switches kHistSwitchCycles after
  // the EOF beat on s_axis_video, before results() (kEofToFrameDoneCycles):
  // results().histogram is a model-only copy that hardware does not hold.
  uint32_t hist_rd_data() const { return hist_.hist_rd_data(); }
  static constexpr int kHistSwitchCycles = 2 + Histogram::kDoneLatencyCycles;
  const FrameErrorCounters& error_counters() const { return fc_.counters(); }
  // Good frames whose results were not published because they ended while
  // moment_gen was still combining the previous frame, or started while the
  // histogram had no cleared bank (saturating; docs/blocks/pipeline.md).
  uint32_t frames_overrun() const { return mom_.overrun_count(); }
  // moment_gen's result words: the published moments as register words, one
  // per cycle for MomentGen::kMomentWords cycles from frame_done() on (into
  // the device's result store).
  MomentWord mom_wr() const { return mom_.mom_wr(); }
  uint32_t run_trailers_lost() const { return runs_.trailers_lost(); }
  uint32_t run_fifo_occupancy() const { return runs_.fifo_occupancy(); }

  // The corridor blocks (meaningful with has_corridor()): the edge block
  // taps thresh_lut's output (the LUT remap) like the stage-3 blocks, its
  // m_axis_edges feeds the hough block's s_axis_edges (tready = the hough's).
  const EdgeDetector& edge() const { return edge_; }
  const Hough& hough() const { return hough_; }
  // The hough block's read port output (0 without a read on the last edge).
  uint32_t hough_rd_data() const { return has_corridor_ ? hough_.rd_data() : 0u; }
  // One-cycle pulse: the hough block published a frame (its done).
  bool hough_done() const { return has_corridor_ && hough_.done(); }
  // STATUS.HOUGH_PENDING: the edge block holds an edge point or a trailer
  // (staged for its FIFO, in the FIFO or its output register), or the hough
  // block votes an edge or publishes.
  bool corridor_pending() const;
  // Live, saturating: cycles in which the edge block offered a beat the hough
  // block did not take (HOUGH_STALLS).
  uint32_t hough_stalls() const { return hough_stalls_q_; }

  // The orientation block (meaningful with has_orientation()): it taps
  // thresh_lut's output like the edge block.
  const Orientation& orientation() const { return ori_; }
  // Its read port output (0 without a read on the last edge, or without it).
  uint32_t ori_rd_data() const { return has_orientation_ ? ori_.hist_rd_data() : 0u; }

  // Fast path: one well-formed frame of width x height (must equal the
  // configuration that becomes active), processed as clock() would after the
  // shadow -> active copy of its SOF. Returns the published results (and
  // updates results()); the runs go to *runs_out (if given) in stream order,
  // not into the FIFO, and without the trailer. Equal to the clocked path
  // when the pipeline is idle before the frame (no frame open, FIFO empty,
  // results published) and m_axis_runs_tready = 1 with a FIFO of >= 3
  // entries. Throws std::invalid_argument on a geometry mismatch and
  // std::logic_error when the pipeline is not idle. With the corridor
  // blocks, the frame's edge points (EdgeDetector::scan_frame of the remap,
  // if the edge configuration enables the frame) and its trailer go through
  // Hough::process_frame: hough() then holds the frame's accumulator and
  // counters as the clocked path leaves them once the hough block is idle,
  // if the edge FIFO never fills (edge() keeps its state: EDGE_COUNT /
  // EDGE_DROPPED of the frame are the trailer's, in hough().counters()).
  // With the orientation block enabled for the frame (ORI_CONTROL.ENABLE),
  // Orientation::publish_frame votes the remap: orientation() then holds the
  // frame's histogram and counters as the clocked path publishes them when
  // the blanking before the frame outlasts the block's sweep (bins cycles).
  FrameResults process_frame(const uint8_t* grey, int width, int height, size_t stride_bytes,
                             std::vector<RunRecord>* runs_out);

 private:
  // Configuration fields that travel down the pipeline with the SOF.
  struct StageConfig {
    RunScanConfig runs;
    bool hist_source_remap = false;
    ClassWindow class_window{};
    EdgeConfig edge{};
    OrientationConfig ori{};
  };
  // What the result registers take from the frame_check side, carried two
  // stages to the point where the frame reaches histogram/moment/run.
  struct FrameMeta {
    uint32_t frame_index = 0;
    FrameErrorCounters errors;
    uint64_t cycles_in_frame = 0;
  };

  StageConfig stage_config(const PipelineConfig& cfg) const {
    return {RunScanConfig::from(cfg), cfg.hist_source_remap, cfg.class_window, edge_shadow_,
            ori_shadow_};
  }
  void build_tables();

  PipelineConfig shadow_;  // host-written

  FrameCheck fc_;
  ThreshLut lut_;
  Histogram hist_;
  MomentGen mom_;
  ClassMoments cls_;
  RunScanner runs_;
  EdgeDetector edge_;
  Hough hough_;
  Orientation ori_;
  bool has_class_moments_;
  bool has_corridor_;
  bool has_orientation_;
  OrientationConfig ori_shadow_{};          // host-written, ORI_CONTROL's reset values
  EdgeConfig edge_shadow_{};                // host-written, EDGE_CONTROL's reset values
  HoughConfig hough_cfg_{.enable = false};  // HOUGH_CONTROL / HOUGH_GEOMETRY's reset values
  uint32_t hough_stalls_q_ = 0;

  StageConfig cfg_fc_{};   // latched with the SOF beat by frame_check
  StageConfig cfg_lut_{};  // latched when the SOF pixel enters thresh_lut

  uint64_t cycle_q_ = 0;      // free-running cycle counter
  uint64_t sof_cycle_q_ = 0;  // cycle of the open frame's SOF pixel
  FrameMeta meta_fc_q_{};     // frame_check's EOF pixel (its output stage)
  FrameMeta meta_lut_q_{};    // thresh_lut's output stage

  bool hist_accept_q_ = false;  // the frame that ended on the last edge will be published
  HistogramResults staged_hist_q_{};
  RunStats staged_runs_q_{};
  FrameMeta staged_meta_q_{};

  FrameResults results_q_{};
  bool frame_done_q_ = false;

  // Fast path scratch (no hardware meaning).
  std::array<uint8_t, 256> remap_table_{};
  std::array<uint8_t, 256> mask_table_{};
  std::array<uint8_t, 256> class_table_{};
  std::vector<uint8_t> remap_row_;
  std::vector<uint8_t> mask_row_;
  std::vector<uint8_t> class_row_;
  std::vector<uint8_t> remap_frame_;
  std::vector<EdgeRecord> edge_points_;
  std::vector<uint64_t> edge_words_;
};

}  // namespace ceilnav::stream
