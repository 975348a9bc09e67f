// The device driver: identification, configuration and the per-frame
// readout, through the registers of docs/registers.md on any Bus backend.
#pragma once

#include <cstdint>
#include <deque>
#include <vector>

#include "common/corridor_results.hpp"
#include "common/edge_record.hpp"
#include "common/hough_params.hpp"
#include "common/pipeline_config.hpp"
#include "common/results.hpp"
#include "host/bus.hpp"

namespace ceilnav::host {

enum class RunSink : uint8_t {
  kStream,     // runs arrive on m_axis_runs (Bus::take_run_stream)
  kRegisters,  // the driver pops them through RUN_WORD0..3
};

struct DriverOptions {
  RunSink run_sink = RunSink::kStream;
  uint64_t irq_timeout_cycles = 100'000'000;
  uint64_t run_timeout_cycles = 10'000'000;    // waiting for the frame's trailer
  uint64_t hough_timeout_cycles = 50'000'000;  // waiting for the hough to publish the frame
};

struct FrameReadout {
  stream::FrameResults results;         // the result registers of the frame
  std::vector<stream::RunRecord> runs;  // the frame's runs in stream order
  bool trailer_seen = false;
  uint16_t trailer_flags = 0;      // stream::RunTrailerFlags of the frame's trailer
  uint16_t trailer_run_count = 0;  // runs emitted, as the trailer counts them (saturating)
  uint32_t frame_count = 0;        // FRAME_COUNT at readout
  uint32_t eof_to_irq_cycles = 0;  // EOF_TO_IRQ_CYCLES at readout
  uint32_t intr_state = 0;         // INTR_STATE bits seen (and cleared) for this frame
  bool consistent = true;          // RES_FRAME_INDEX unchanged across the readout
};

// ORI_CONTROL: the orientation block's configuration (stream::OrientationConfig).
struct OrientationControl {
  bool enable = true;
  uint16_t threshold = 16;  // 12 bits: a gradient votes if its weight > threshold
};

// The orientation block's published histogram and counters.
struct OrientationReadout {
  bool valid = false;          // ORI_STATUS.RESULTS_VALID
  uint32_t frames = 0;         // ORI_FRAMES (publications since reset)
  uint32_t skipped = 0;        // ORI_SKIPPED
  uint32_t votes = 0;          // ORI_VOTES of the published frame
  std::vector<uint32_t> bins;  // ORI_STATUS.NUM_BINS bins; bin k centred on k * 90 / size degrees
  bool consistent = true;      // ORI_FRAMES unchanged across the readout
};

class Driver {
 public:
  explicit Driver(Bus& bus, const DriverOptions& options = {});

  // Reads ID and VERSION; throws std::runtime_error if this is not a ceilnav
  // device of the major version the driver knows. Returns the VERSION word.
  uint32_t identify();

  // Reads FEATURES (the device configuration), then writes the whole configuration (geometry,
  // all 256 LUT entries with their pixel classes, scanner settings, histogram source, and the
  // class window if the device has class_moments), clears INTR_STATE, enables the FRAME_DONE
  // interrupt and the video gate. Takes effect at the next SOF; call it between frames (after
  // read_frame, before the next frame starts), or the LUT may change across two frames.
  void configure(const stream::PipelineConfig& cfg);

  // FEATURES.CLASS_MOMENTS as read by the last configure(): without class_moments (the tape
  // device) the readout's class_moments stay 0 and their registers are not touched.
  bool has_class_moments() const { return has_class_moments_; }
  // FEATURES.CORRIDOR as read by the last configure(): the edge and hough blocks.
  bool has_corridor() const { return has_corridor_; }
  // Writes EDGE_CONTROL, HOUGH_CONTROL and HOUGH_GEOMETRY (throws
  // std::runtime_error on a device without the corridor blocks). Like
  // configure(): between frames; the edge block takes EDGE_CONTROL at the
  // next SOF, the hough block its configuration with the frame's first edge.
  void configure_corridor(const stream::EdgeConfig& edge, const stream::HoughConfig& hough);
  // After read_frame() of a frame the edge block took: waits until the hough
  // block has published it (STATUS.HOUGH_PENDING = 0), then reads the
  // accumulator through HOUGH_INDEX / HOUGH_DATA (n_theta x 2^RHO_BITS
  // reads, HOUGH_SHAPE) with the shape, counters and flags. Throws
  // std::runtime_error on a timeout or without the corridor blocks.
  stream::CorridorReadout read_corridor();

  // FEATURES.ORIENTATION as read by the last configure(): the orientation block.
  bool has_orientation() const { return has_orientation_; }
  // Writes ORI_CONTROL (throws std::runtime_error on a device without the
  // orientation block). Like configure(): between frames; the block takes it
  // at the next SOF.
  void configure_orientation(const OrientationControl& ori);
  // The published orientation histogram through ORI_INDEX / ORI_DATA
  // (ORI_STATUS.NUM_BINS reads) with its counters. The block publishes a
  // frame Orientation::kDoneLatencyCycles after its EOF pixel, before the
  // frame's FRAME_DONE: after read_frame() of a frame it took, the histogram
  // is that frame's unless ORI_SKIPPED moved. Throws std::runtime_error
  // without the orientation block.
  OrientationReadout read_orientation();

  // Waits for FRAME_DONE, acknowledges it, reads the result registers and
  // the frame's runs. Throws std::runtime_error on a timeout.
  FrameReadout read_frame();

 private:
  stream::FrameResults read_results();
  void read_runs(FrameReadout& out);
  bool next_run_entry(stream::RunBeat& beat);

  Bus& bus_;
  DriverOptions options_;
  std::deque<stream::RunBeat> stream_backlog_;  // received beats not yet consumed
  bool has_class_moments_ = true;
  bool has_corridor_ = false;
  bool has_orientation_ = false;
  stream::EdgeConfig edge_cfg_{};
  stream::HoughConfig hough_cfg_{};
};

}  // namespace ceilnav::host
