#pragma once
// Retrieval by structure for the structure localizer (structure_localizer.h): an image (the camera's, or one channel
// of a view's quasi-image) becomes a coarse grid of sign-free gradient-orientation histograms, and a camera grid is
// compared with a view's grids under shifts of whole cells (the camera turned left/right, up/down from the view).
//
// Cell vector: the orientation field's per-pixel votes (crossmodal_descriptors.h: orientations modulo 180 deg, each
// vote its magnitude over the local RMS magnitude) summed over the cell, minus their mean over the bins, over their
// sum: its length is how strongly one orientation dominates the cell (0 for a flat or isotropic cell), its
// direction which one. Score of a shift: the normalised correlation of the overlapping cells' vectors, averaged over
// the view's channels; only shifts whose valid view cells cover min_overlap of the camera grid count.
#include <opencv2/core.hpp>
#include <quasiloc/frontend/crossmodal_descriptors.h>
#include <vector>

namespace quasiloc::reloc
{
struct OrientationGrid
{
    int cols = 0, rows = 0, bins = 0;
    std::vector<float> vectors;  ///< cols * rows cells of bins values, row-major
    std::vector<uint8_t> valid;  ///< per cell

    const float* cell(int c, int r) const { return vectors.data() + size_t(r * cols + c) * size_t(bins); }
    bool isValid(int c, int r) const { return valid[size_t(r * cols + c)] != 0; }
};

/** The grid of `image` (CV_8U or CV_32F) with cells of cell_px pixels (the image's last partial cells dropped).
 *  `valid` (CV_8U, may be empty = all valid): a cell is valid when at least min_valid_share of its pixels are. */
OrientationGrid orientationGrid(const cv::Mat& image, const cv::Mat& valid, int cell_px,
                                const frontend::CrossModalDescriptorOptions& descriptors, double min_valid_share = 0.5);

struct GridShift
{
    float score = -2;  ///< -2: no shift had the overlap
    /** (score - mean) / standard deviation of the scores over all shifts with the overlap: how far the best shift
     *  stands out (a view that correlates with any image at every shift does not). 0 with one shift. */
    float peak = 0;
    int dx = 0, dy = 0;  ///< camera cell (c, r) against view cell (c + dx, r + dy)
};

/** The best shift of the views' channel grids (all of one size, the camera grid's) against the camera grid. */
GridShift bestGridShift(const OrientationGrid& camera, const std::vector<const OrientationGrid*>& view_channels,
                        int max_dx, int max_dy, double min_overlap);

}  // namespace quasiloc::reloc
