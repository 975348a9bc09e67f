// The corridor file (docs/navigation_io.md, "Corridor files"): the example
// file is the built-in corridor, files round-trip exactly, and every kind of
// bad file is refused with a message naming the file, the key and the fault.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>

#include "golden/corridor/corridor_file.hpp"

namespace ceilnav::golden::corridor {
namespace {

const std::string kMinimal = R"(format: ceilnav_corridor
version: 1
geometry: {width_m: 2.0, ceiling_height_m: 2.6, length_m: 30}
)";

// The message of the CorridorError that parsing `text` throws ("" if none).
std::string error_of(const std::string& text) {
  try {
    parse_corridor(text, "test.yaml");
  } catch (const CorridorError& e) {
    return e.what();
  }
  return "";
}

TEST(CorridorFile, ExampleFileIsTheBuiltInCorridor) {
  const std::string path = std::string(CEILNAV_SOURCE_DIR) + "/examples/corridor/default.yaml";
  const CorridorFile file = load_corridor(path);
  EXPECT_EQ(file.corridor, default_corridor())
      << "regenerate examples/corridor/default.yaml from corridor_to_yaml({default_corridor(), "
         "default_pose()})";
  ASSERT_TRUE(file.camera.has_value());
  EXPECT_EQ(*file.camera, default_pose());
}

// The held-out corridors of docs/corridor.md ("Held-out corridors") load,
// differ from the built-in corridor, carry a camera, and leave room for the
// built-in drives of ceilnav corridor: 40 m beyond the camera (16 m of
// learning, 24 m of the weave) and +-0.8 m about its y inside the walls.
TEST(CorridorFile, HeldOutExampleFilesLoadAndFitTheBuiltInDrives) {
  int n = 0;
  for (const auto& entry : std::filesystem::directory_iterator(std::string(CEILNAV_SOURCE_DIR) +
                                                               "/examples/corridor")) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("study_", 0) != 0) continue;
    SCOPED_TRACE(name);
    const CorridorFile f = load_corridor(entry.path().string());
    ASSERT_TRUE(f.camera.has_value());
    EXPECT_FALSE(f.corridor == default_corridor() && *f.camera == default_pose());
    EXPECT_LT(f.camera->x_m + 40.0, f.corridor.x_end_m());
    EXPECT_LT(std::abs(f.camera->y_m) + 0.8, 0.5 * f.corridor.width_m);
    ++n;
  }
  EXPECT_GE(n, 15);
}

TEST(CorridorFile, RoundTripsExactly) {
  CorridorFile file{default_corridor(), default_pose()};
  file.corridor.far_end_open = true;
  file.corridor.lamps.first_x_m = 0.1 + 0.2;  // not a short decimal
  file.camera->pan_rad = 1.0 / 3.0;
  EXPECT_EQ(parse_corridor(corridor_to_yaml(file)), file);
  const auto path = std::filesystem::temp_directory_path() /
                    ("ceilnav_corridor_" + std::to_string(::getpid()) + ".yaml");
  save_corridor(file, path.string());
  EXPECT_EQ(load_corridor(path.string()), file);
  EXPECT_FALSE(std::filesystem::exists(path.string() + ".tmp"));
  std::filesystem::remove(path);
  // Without a camera, and in JSON (read as YAML).
  file.camera.reset();
  EXPECT_EQ(parse_corridor(corridor_to_yaml(file)), file);
  const CorridorFile json = parse_corridor(
      R"({"format": "ceilnav_corridor", "version": 1,
          "geometry": {"width_m": 2.0, "ceiling_height_m": 2.6, "length_m": 30}})");
  EXPECT_EQ(json, parse_corridor(kMinimal));
}

TEST(CorridorFile, MinimalFileTakesTheDefaults) {
  const CorridorFile file = parse_corridor(kMinimal);
  Corridor expected;
  expected.width_m = 2.0;
  expected.ceiling_height_m = 2.6;
  expected.length_m = 30.0;
  EXPECT_EQ(file.corridor, expected);
  EXPECT_TRUE(file.corridor.lamps.rows_y_m.empty());
  EXPECT_FALSE(file.camera.has_value());
}

TEST(CorridorFile, CameraAnglesInDegreesOrRadians) {
  const CorridorFile deg = parse_corridor(
      kMinimal + "camera: {x_m: 1, y_m: 0.2, height_m: 1, pan_deg: 10, tilt_deg: 30}\n");
  ASSERT_TRUE(deg.camera.has_value());
  EXPECT_DOUBLE_EQ(deg.camera->pan_rad, 10.0 * std::numbers::pi / 180.0);
  EXPECT_DOUBLE_EQ(deg.camera->tilt_rad, 30.0 * std::numbers::pi / 180.0);
  EXPECT_EQ(deg.camera->swing_rad, 0.0);
  const CorridorFile rad =
      parse_corridor(kMinimal + "camera: {x_m: 1, y_m: 0.2, height_m: 1, swing_rad: -0.25}\n");
  EXPECT_EQ(rad.camera->swing_rad, -0.25);
}

TEST(CorridorFile, BadFilesNameTheKeyAndTheFault) {
  struct Case {
    std::string text, expected;
  };
  const std::string g = "geometry: {width_m: 2.0, ceiling_height_m: 2.6, length_m: 30}\n";
  const std::string head = "format: ceilnav_corridor\nversion: 1\n";
  const Case cases[] = {
      {"[1, 2", "test.yaml: not YAML or JSON"},
      {"- 1\n- 2\n", "test.yaml: top level is not a map of keys"},
      {head, "test.yaml: geometry: missing"},
      {"version: 1\n" + g, "test.yaml: format: missing"},
      {"format: ceilnav_course\nversion: 1\n" + g, "format: must be 'ceilnav_corridor'"},
      {"format: ceilnav_corridor\nversion: 2\n" + g, "version: must be 1"},
      {head + g + "colour: red\n", "test.yaml: colour: unknown key"},
      {head + "geometry: {width_m: 2.0, ceiling_height_m: 2.6}\n", "geometry.length_m: missing"},
      {head + "geometry: {width_m: wide, ceiling_height_m: 2.6, length_m: 30}\n",
       "geometry.width_m: 'wide' is not a number"},
      {head + "geometry: {width_m: [2], ceiling_height_m: 2.6, length_m: 30}\n",
       "geometry.width_m: must be a number"},
      {head + "geometry: {width_m: -2, ceiling_height_m: 2.6, length_m: 30}\n",
       "geometry.width_m: must be finite and > 0"},
      {head + "geometry: {width_m: .nan, ceiling_height_m: 2.6, length_m: 30}\n",
       "geometry.width_m: must be finite"},
      {head + "geometry: {width_m: 2, ceiling_height_m: 2.6, length_m: 30, far_end: door}\n",
       "geometry.far_end: must be 'wall' or 'open'"},
      {head + "geometry: 3\n", "geometry: must be a map"},
      {head + g + "surfaces: {wall_albedo: -0.1}\n",
       "surfaces.wall_albedo: must be finite and >= 0"},
      {head + g + "lamps: {length_m: 1}\n", "lamps.rows_y_m: missing"},
      {head + g + "lamps: {rows_y_m: 0.5}\n", "lamps.rows_y_m: must be a sequence"},
      {head + g + "lamps: {rows_y_m: [0.95]}\n", "lamps.rows_y_m[0]: the row must lie inside"},
      {head + g + "lamps: {rows_y_m: [0.4, 0.2]}\n", "lamps.rows_y_m[1]: rows must increase"},
      {head + g + "lamps: {rows_y_m: [0], length_m: 4, spacing_m: 3}\n",
       "lamps.length_m: must be < spacing_m"},
      {head + g + "seams: {along_pitch_m: 0.005, width_m: 0.01}\n",
       "seams.width_m: must be < the pitch"},
      {head + g + "cornice: {albedo: 0.9}\n", "cornice.height_m: missing"},
      {head + g + "cornice: {height_m: 1.5}\nskirting: {height_m: 1.2}\n",
       "cornice.height_m: cornice and skirting must leave some wall"},
      {head + g + "doors: {wall: left}\n", "doors: must be a sequence"},
      {head + g + "doors: [{wall: up, x_m: 2, width_m: 1, height_m: 2}]\n",
       "doors[0].wall: must be 'left' or 'right'"},
      {head + g + "doors: [{wall: left, x_m: 2, width_m: 0, height_m: 2}]\n",
       "doors[0].width_m: must be finite and > 0"},
      {head + g + "doors: [{wall: left, x_m: 29.5, width_m: 1, height_m: 2}]\n",
       "doors[0].x_m: the door and its frame must lie on the wall"},
      {head + g + "doors: [{wall: left, x_m: 2, width_m: 1, height_m: 2.6}]\n",
       "doors[0].height_m: the door and its frame must end below the cornice"},
      {head + g + "camera: {x_m: 1, y_m: 0, height_m: 1, pan_rad: 0, pan_deg: 0}\n",
       "camera: needs at most one of pan_rad and pan_deg"},
      {head + g + "camera: {x_m: 1, y_m: 1.5, height_m: 1}\n",
       "camera.y_m: must lie between the walls"},
      {head + g + "camera: {x_m: 1, y_m: 0, height_m: 3}\n",
       "camera.height_m: must lie between floor and ceiling"},
      {head + g + "camera: {x_m: -9, y_m: 0, height_m: 1}\n",
       "camera.x_m: must lie inside the corridor"},
      {head + g + "camera: {y_m: 0, height_m: 1}\n", "camera.x_m: missing"},
  };
  for (const Case& c : cases) {
    const std::string message = error_of(c.text);
    EXPECT_NE(message.find(c.expected), std::string::npos)
        << "file:\n"
        << c.text << "\nexpected '" << c.expected << "' in '" << message << "'";
    EXPECT_EQ(message.rfind("test.yaml: ", 0), 0U) << message;
  }
  EXPECT_THROW(load_corridor("/nonexistent/corridor.yaml"), CorridorError);
}

}  // namespace
}  // namespace ceilnav::golden::corridor
