// LighterGlue through libtorch (TorchScript, ../shared/models/README.md), built as the shared module
// libquasiloc_lighterglue_torch.so that the front-end loads on first use (network.h). The only file of the project
// that includes libtorch headers (they cost ~17 s of compile time per file).
#include <ATen/Context.h>
#include <torch/script.h>

#include <cstring>

#include "network.h"

#if defined(__SSE__)
#include <xmmintrin.h>
#endif

namespace quasiloc::frontend::detail
{
namespace
{
/** Flush-to-zero / denormals-are-zero for the duration of a forward pass. The attention softmax produces
 *  denormals, and matrix products on denormal inputs run about 40x slower (models README). The flags live in the
 *  calling thread's MXCSR: they are restored afterwards so the caller's own arithmetic (Ceres, ...) keeps
 *  IEEE behaviour. */
class FlushDenormalScope
{
   public:
    FlushDenormalScope()
    {
#if defined(__SSE__)
        saved_ = _mm_getcsr();
#endif
        at::globalContext().setFlushDenormal(true);
    }
    ~FlushDenormalScope()
    {
#if defined(__SSE__)
        _mm_setcsr(saved_);
#else
        at::globalContext().setFlushDenormal(false);
#endif
    }

   private:
    unsigned saved_ = 0;
};

/** A [1, rows, cols] float tensor viewing a continuous CV_32F matrix (no copy; the network does not write it). */
torch::Tensor view3(const cv::Mat& m)
{
    return torch::from_blob(const_cast<float*>(m.ptr<float>()), {1, m.rows, m.cols}, torch::kFloat32);
}

class TorchLighterGlue : public LighterGlueBackend
{
   public:
    std::string load(const std::string& model_path) override
    {
        try
        {
            module_ = torch::jit::load(model_path);
            module_.eval();
        }
        catch (const std::exception& e)
        {
            return errorText(e);
        }
        return "";
    }

    std::string logAssignment(const cv::Mat& kpts0, const cv::Mat& kpts1, const cv::Mat& desc0, const cv::Mat& desc1,
                              cv::Mat& out) override
    {
        try
        {
            const FlushDenormalScope flush_denormals;
            const c10::InferenceMode inference;
            torch::Tensor scores = module_.forward({view3(kpts0), view3(kpts1), view3(desc0), view3(desc1)}).toTensor();
            scores = scores.to(torch::kFloat32).contiguous();
            const int rows = kpts0.rows + 1, cols = kpts1.rows + 1;
            if (scores.dim() != 3 || scores.size(1) != rows || scores.size(2) != cols)
                return "expected scores of shape [1, M+1, N+1], got " + toString(scores.sizes());
            out.create(rows, cols, CV_32F);
            std::memcpy(out.ptr<float>(), scores.data_ptr<float>(), sizeof(float) * size_t(rows) * size_t(cols));
        }
        catch (const std::exception& e)
        {
            return errorText(e);
        }
        return "";
    }

   private:
    static std::string errorText(const std::exception& e)
    {
        if (const auto* c10_error = dynamic_cast<const c10::Error*>(&e)) return c10_error->what_without_backtrace();
        return e.what();
    }
    static std::string toString(c10::IntArrayRef sizes)
    {
        std::string s = "[";
        for (size_t k = 0; k < sizes.size(); ++k) s += (k ? ", " : "") + std::to_string(sizes[k]);
        return s + "]";
    }

    torch::jit::Module module_;
};
}  // namespace
}  // namespace quasiloc::frontend::detail

extern "C" quasiloc::frontend::detail::LighterGlueBackend* quasiloc_create_lighterglue_backend()
{
    return new quasiloc::frontend::detail::TorchLighterGlue();
}
