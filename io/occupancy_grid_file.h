#ifndef SPLAM_IO_OCCUPANCY_GRID_FILE_H_
#define SPLAM_IO_OCCUPANCY_GRID_FILE_H_

#include <string>
#include <vector>

#include "estimation/occupancy_grid.h"
#include "io/result.h"
#include "kernel/trajectory.h"

// Occupancy grids in ROS map_server's format (the map_saver's output, nav2's map_server input):
// a YAML file
//     image: map.pgm          (relative to the YAML file)
//     mode: trinary
//     resolution: 0.05        (m per cell)
//     origin: [x, y, yaw]     (the pose of the lower-left pixel in the map frame; yaw 0 here)
//     negate: 0
//     occupied_thresh: 0.65
//     free_thresh: 0.196
// and a grey image whose top row is the largest y. Pixel value v reads as occupancy
// p = (255 - v) / 255 (v / 255 with negate); in trinary mode p > occupied_thresh is occupied,
// p < free_thresh free, anything between unknown. Written as map_saver does: 0 occupied, 254 free,
// 205 unknown.
namespace splam::io {

// `yaml_path` and the PGM image beside it (same name, .pgm). Cells are occupied or free by
// `thresholds` (OccupancyGridOptions' occupied_threshold and free_threshold, also written to the
// YAML file).
kernel::Status WriteOccupancyGrid(const estimation::OccupancyGrid& grid,
                                  const std::string& yaml_path,
                                  const estimation::OccupancyGridOptions& thresholds);

// A map_server YAML file and its image (PGM, PNG and the other formats OpenCV reads; trinary,
// scale and raw modes; negate). Known cells get the log-odds of the probability their pixel
// states (clamped to [0.01, 0.99]), unknown ones stay unobserved. An error names the file and,
// for a key, its line. A yaw other than 0 is refused (splam's grids are axis-aligned).
Result<estimation::OccupancyGrid> ReadOccupancyGrid(const std::string& yaml_path);

// A picture of the grid (SVG or PNG by extension), every cell a sharp square: occupied black,
// free white, unknown grey, observed but undecided cells grey by their probability; `path` (the
// estimate) drawn over it; title, legend and scale bar.
kernel::Status SaveOccupancyGridPicture(const estimation::OccupancyGrid& grid,
                                        const estimation::OccupancyGridOptions& thresholds,
                                        const std::string& title, const kernel::Trajectory& path,
                                        const std::vector<std::string>& files);

}  // namespace splam::io

#endif  // SPLAM_IO_OCCUPANCY_GRID_FILE_H_
