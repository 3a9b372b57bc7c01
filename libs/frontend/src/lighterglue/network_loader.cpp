// LighterGlueNetwork: loads the libtorch module (network.h says why it is a separate module) and forwards to it.
// QUASILOC_LIGHTERGLUE_MODULE, the module's path in the build tree, is defined by CMake only when libtorch was
// found; without it every LighterGlue entry point says that this build has no libtorch.
#include <dlfcn.h>

#include <mutex>
#include <quasiloc/core/error.h>

#include "network.h"

namespace quasiloc::frontend::detail
{
namespace
{
/** The module's factory, loaded once per process. The module is never unloaded: libtorch does not support being
 *  unloaded (its operator registries live in static objects). */
CreateLighterGlueBackendFn backendFactory()
{
#ifdef QUASILOC_LIGHTERGLUE_MODULE
    static std::once_flag once;
    static CreateLighterGlueBackendFn factory = nullptr;
    static std::string error;
    std::call_once(once, [] {
        void* handle = ::dlopen(QUASILOC_LIGHTERGLUE_MODULE, RTLD_NOW | RTLD_LOCAL);
        if (!handle)
        {
            const char* e = ::dlerror();
            error = std::string("cannot load the LighterGlue libtorch module: ") + (e ? e : "?");
            return;
        }
        factory = reinterpret_cast<CreateLighterGlueBackendFn>(::dlsym(handle, kCreateLighterGlueBackendSymbol));
        if (!factory) error = std::string("the module does not export ") + kCreateLighterGlueBackendSymbol;
    });
    core::require(factory != nullptr, QUASILOC_LIGHTERGLUE_MODULE, error);
    return factory;
#else
    throw core::InputError("LighterGlue",
                           "this build has no libtorch (install libtorch-dev, then configure with "
                           "-DQUASILOC_WITH_TORCH=ON)");
#endif
}
}  // namespace

bool lighterGlueCompiledIn()
{
#ifdef QUASILOC_LIGHTERGLUE_MODULE
    return true;
#else
    return false;
#endif
}

LighterGlueNetwork::LighterGlueNetwork(const std::string& model_path) : backend_(backendFactory()())
{
    core::require(backend_ != nullptr, "LighterGlue", "the libtorch module made no backend");
    const std::string error = backend_->load(model_path);
    core::require(error.empty(), model_path, "cannot load the LighterGlue TorchScript model: " + error);
}

LighterGlueNetwork::~LighterGlueNetwork() = default;

cv::Mat LighterGlueNetwork::logAssignment(const cv::Mat& kpts0, const cv::Mat& kpts1, const cv::Mat& desc0,
                                          const cv::Mat& desc1)
{
    for (const cv::Mat* m : {&kpts0, &kpts1, &desc0, &desc1})
        core::require(m->type() == CV_32FC1 && m->isContinuous() && m->rows > 0, "LighterGlue input",
                      "expected non-empty continuous CV_32F matrices");
    cv::Mat scores;
    const std::string error = backend_->logAssignment(kpts0, kpts1, desc0, desc1, scores);
    core::require(error.empty(), "LighterGlue forward", error);
    return scores;
}
}  // namespace quasiloc::frontend::detail
