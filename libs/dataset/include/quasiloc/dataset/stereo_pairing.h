#pragma once
// StereoPairer: pairs left and right images by timestamp while they stream in (a ROS bag's two camera topics).
// Each side's images come in increasing time; a left image pairs with the first right image within the tolerance.
// An image the other side has gone past (its latest time is later than this one's plus the tolerance) can no longer
// pair: it is reported as unpaired, so that the caller can free it. The images themselves stay with the caller;
// the pairer sees ids.
#include <cstdint>
#include <deque>
#include <vector>

namespace quasiloc::dataset
{
class StereoPairer
{
   public:
    struct Pair
    {
        std::int64_t left_ns = 0, right_ns = 0;
        std::size_t left_id = 0, right_id = 0;
    };
    struct Unpaired
    {
        bool left = true;  ///< which side the image was on
        std::int64_t t_ns = 0;
        std::size_t id = 0;
        bool out_of_order = false;  ///< not later than the previous image of its side
    };

    /** `max_pending` bounds the images kept waiting while the other side is silent (its oldest go unpaired). */
    explicit StereoPairer(std::int64_t tolerance_ns, std::size_t max_pending = 64);

    void addLeft(std::int64_t t_ns, std::size_t id) { add(true, t_ns, id); }
    void addRight(std::int64_t t_ns, std::size_t id) { add(false, t_ns, id); }
    /** At the end of the data: what still waits is unpaired. */
    void finish();

    /** The pairs and unpaired images found since the last call, in time order. */
    std::vector<Pair> takePairs();
    std::vector<Unpaired> takeUnpaired();

    std::size_t numPairs() const { return num_pairs_; }
    std::size_t numUnpairedLeft() const { return num_unpaired_[0]; }
    std::size_t numUnpairedRight() const { return num_unpaired_[1]; }

   private:
    struct Pending
    {
        std::int64_t t_ns;
        std::size_t id;
    };
    void add(bool left, std::int64_t t_ns, std::size_t id);
    void match();
    void dropFront(bool left);

    std::int64_t tolerance_ns_;
    std::size_t max_pending_;
    std::deque<Pending> pending_[2];  ///< [0] left, [1] right
    bool seen_[2] = {false, false};
    std::int64_t latest_ns_[2] = {0, 0};
    std::vector<Pair> pairs_;
    std::vector<Unpaired> unpaired_;
    std::size_t num_pairs_ = 0, num_unpaired_[2] = {0, 0};
};

}  // namespace quasiloc::dataset
