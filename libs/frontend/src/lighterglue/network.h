#pragma once
// The LighterGlue network behind a plain header. libtorch lives in a separate shared module
// (network_torch.cpp -> libquasiloc_lighterglue_torch.so, built only when libtorch is found) that the front-end
// loads with dlopen the first time a LighterGlue matcher is made. Why not link libtorch into the library: every
// process that links the front-end (programs, and each of the hundreds of unit tests ctest runs one process at a
// time) would load libtorch at startup, ~1 s each on a loaded 2-core machine, whether it matches with LighterGlue
// or not; and libtorch's headers cost ~17 s of compile time per file, so exactly one file includes them.
#include <memory>
#include <opencv2/core.hpp>
#include <string>

namespace quasiloc::frontend::detail
{
/** True when this build has the libtorch module (CMake found libtorch). */
bool lighterGlueCompiledIn();

/** What the libtorch module implements. Errors come back as text, so that no exception type has to cross the
 *  shared-object boundary. */
class LighterGlueBackend
{
   public:
    virtual ~LighterGlueBackend() = default;
    /** Loads the TorchScript model: "" on success, else what went wrong. */
    virtual std::string load(const std::string& model_path) = 0;
    /** See LighterGlueNetwork::logAssignment: "" on success, else what went wrong. */
    virtual std::string logAssignment(const cv::Mat& kpts0, const cv::Mat& kpts1, const cv::Mat& desc0,
                                      const cv::Mat& desc1, cv::Mat& scores) = 0;
};
/** The module's one exported function (extern "C"): a new backend, owned by the caller. */
using CreateLighterGlueBackendFn = LighterGlueBackend* (*)();
constexpr const char* kCreateLighterGlueBackendSymbol = "quasiloc_create_lighterglue_backend";

class LighterGlueNetwork
{
   public:
    /** Loads the libtorch module (once per process) and the TorchScript model. InputError naming model_path if
     *  the model cannot be loaded, naming the module if it cannot, or saying that this build has no libtorch. */
    explicit LighterGlueNetwork(const std::string& model_path);
    ~LighterGlueNetwork();
    LighterGlueNetwork(const LighterGlueNetwork&) = delete;
    LighterGlueNetwork& operator=(const LighterGlueNetwork&) = delete;

    /** The log-assignment matrix, CV_32F (M+1)x(N+1) (last row / column: unmatched), for keypoints already
     *  normalised (Mx2 and Nx2 CV_32F) and descriptors (MxD, NxD CV_32F, D = 64 for XFeat). M, N >= 1. */
    cv::Mat logAssignment(const cv::Mat& kpts0, const cv::Mat& kpts1, const cv::Mat& desc0, const cv::Mat& desc1);

   private:
    std::unique_ptr<LighterGlueBackend> backend_;
};
}  // namespace quasiloc::frontend::detail
