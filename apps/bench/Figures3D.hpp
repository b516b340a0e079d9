// rgvc_bench3d --figure: seed 004 §6's Figure 5 (a, b, c) and Figure 6 with the GL stage of seed 001,
// headless through OSMesa (Figure5.cpp, Figure6.cpp; the method comparison is GlWalk.hpp).
//
//   (a) frame time (cull + draw + glFinish) against the number of hidden moving spheres (behind a wall
//       that spans the world), for ZB, VFC and RGVC at 50x30x50 and 100x60x100;
//   (b) the walkthrough of 200 moving and 4,800 static spheres: frame time per frame for ZB, VFC, CHC++
//       alone, Ideal, and RGVC and RGVC + CHC++ at both grid resolutions, interleaved in one run;
//   (c) per frame of that walk: |PVS| of RGVC, RGVC + CHC++ and VFC against the item buffer's count;
//   (6) the grid's opaque and hidden voxels seen from outside, and the scene seen from the viewpoint.
// Output in --out DIR: fig5a.csv, fig5a-median.csv, fig5bc.csv (one row per frame and method, settings
// in `#` lines), fig5a.png, fig5b.png, fig5c.png (scripts/plot_fig5.gp through gnuplot), fig6.png (the walk's
// scene) and fig6-wall.png ((a)'s scene, where the grid's own occlusion shows).
#pragma once

#include "rgvc/grid/Camera.hpp"

#include <string>
#include <vector>

namespace rgvc::bench {

struct FigureConfig {
    bool fig5a = false, fig5b = false, fig5c = false, fig6 = false;
    bool quick = false;          ///< small sizes, a few frames: the test suite's run
    std::string out = "fig5";    ///< output folder (made when missing)
    int width = 640, height = 480;      ///< [Pixels] every method's target
    /// (a): hidden movers per point, and frames measured per point after `warmup5a` unrecorded ones.
    std::vector<int> hidden5a = {0, 1000, 2000, 5000, 10000, 20000, 50000, 100000};
    int frames5a = 6, warmup5a = 2; ///< warm-up: frame 1 turns every hidden mover into a TBV (one-off)
    /// (a): the spheres are icospheres of level `level5a` (20 * 4^level triangles: 2 = 320), and of level
    /// `lodLevel5a` (1 = 80) at points with more than `lodAbove5a` hidden movers. llvmpipe sets up about
    /// 4 million triangles a second in view on this machine, and ZB, VFC and the item buffer draw every
    /// mover: 100,000 spheres of the walk's 1,280 triangles would take half a minute per draw.
    int level5a = 2, lodLevel5a = 1, lodAbove5a = 10000;
    int visible5a = 300;          ///< (a): static spheres in front of the wall (what stays visible)
    int walkFrames = 150;         ///< (b), (c): frames of the walk (the paper's figure shows 150)
    int spheres = 5000, statics = 4800; ///< (b), (c): the walk's spheres, of them static
    int fig6Grid = 100;           ///< Figure 6's grid for the walk: 50 (50x30x50) or 100 (100x60x100)
    bool plots = true;            ///< run gnuplot on the CSVs (skipped with a message when not installed)
    std::string gnuplotScript;    ///< default: scripts/plot_fig5.gp of the source tree
};

/// Parses the --figure options (argv without the program name is given whole; unknown options exit 2
/// with one line). `figures`: 5a, 5b, 5c, 6 or all, comma-separated.
FigureConfig parseFigureConfig(int argc, char** argv);

/// Runs the figures of `config`. Returns the exit status: 0, 1 when any method missed a visible object
/// (or a mover meant to be hidden was visible), 2 when GL is unavailable or a file cannot be written.
int runFigures(const FigureConfig& config);

class GlWalk;

/// Figure 6 (Figure6.cpp): the voxels of the grid culler of `walk`'s method `cullerName` after its last
/// cull, opaque (O) dark, hidden (H) red and, light red, the voxels in view that the traversal never
/// reached (it ended at a hidden shell: hidden as well), seen from outside the grid with `camera` marked, above the
/// scene seen from `camera` (the camera of that cull); written to `path` as PNG. `caption` heads it.
/// @throws std::runtime_error (no such culler, PNG error), GlError.
void writeFigure6(GlWalk& walk, const std::string& cullerName, const Camera3& camera, const std::string& caption,
                  const std::string& path);

} // namespace rgvc::bench
