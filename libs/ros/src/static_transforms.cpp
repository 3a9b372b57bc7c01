// The static transforms of a bag as a tree of frames (static_transforms.h).
#include <quasiloc/core/error.h>
#include <quasiloc/core/pose.h>
#include <quasiloc/ros/static_transforms.h>
#include <set>

using quasiloc::core::InputError;

namespace quasiloc::ros
{
void StaticTransforms::add(const TransformMsg& t)
{
    const auto T_parent_child = core::fromTranslationQuaternion(t.translation, t.rotation.normalized());
    if (!parent_.count(t.child_frame_id)) children_.push_back(t.child_frame_id);
    parent_[t.child_frame_id] = {t.header.frame_id, T_parent_child};
}

bool StaticTransforms::hasFrame(const std::string& frame) const
{
    if (parent_.count(frame)) return true;
    for (const auto& [child, link] : parent_)
        if (link.first == frame) return true;
    return false;
}

StaticTransforms::Up StaticTransforms::up(const std::string& frame) const
{
    Up u;
    u.path.push_back({frame, mrpt::poses::CPose3D()});
    std::set<std::string> seen{frame};
    for (auto it = parent_.find(frame); it != parent_.end(); it = parent_.find(it->second.first))
    {
        const auto& [parent, T_parent_child] = it->second;
        if (!seen.insert(parent).second)
        {
            u.cycle = true;
            break;
        }
        u.path.push_back({parent, T_parent_child + u.path.back().second});
    }
    return u;
}

std::optional<mrpt::poses::CPose3D> StaticTransforms::lookup(const std::string& from, const std::string& to) const
{
    if (from == to) return mrpt::poses::CPose3D();
    const Up a = up(from), b = up(to);
    if (a.cycle || b.cycle) return std::nullopt;
    // The first ancestor of `from` that is also one of `to`: T_from_to = T_common_from^-1 * T_common_to.
    for (const auto& [frame, T_frame_from] : a.path)
        for (const auto& [other, T_other_to] : b.path)
            if (frame == other) return -T_frame_from + T_other_to;
    return std::nullopt;
}

mrpt::poses::CPose3D StaticTransforms::chain(const std::string& from, const std::string& to,
                                             const std::string& where) const
{
    const std::string there = " (transforms there, parent -> child: " + describe() + ")";
    if (from == to) return mrpt::poses::CPose3D();
    for (const std::string* f : {&from, &to})
    {
        core::require(hasFrame(*f), where, "frame '" + *f + "' is in no static transform" + there);
        core::require(!up(*f).cycle, where,
                      "the parents of frame '" + *f + "' lead back to a frame passed before: a cycle" + there);
    }
    const auto T = lookup(from, to);
    core::require(T.has_value(), where, "no chain of static transforms from '" + from + "' to '" + to + "'" + there);
    return *T;
}

std::string StaticTransforms::describeChain(const std::string& from, const std::string& to) const
{
    const Up a = up(from), b = up(to);
    for (size_t i = 0; i < a.path.size(); ++i)
        for (size_t j = 0; j < b.path.size(); ++j)
            if (a.path[i].first == b.path[j].first)
            {
                std::string s = from;
                for (size_t k = 1; k <= i; ++k) s += " <- " + a.path[k].first;
                for (size_t k = j; k-- > 0;) s += " -> " + b.path[k].first;
                return s;
            }
    return from + " ... " + to + " (not connected)";
}

std::string StaticTransforms::describe() const
{
    std::string s;
    for (const std::string& child : children_) s += (s.empty() ? "" : ", ") + parent_.at(child).first + " -> " + child;
    return s.empty() ? "none" : s;
}

StaticTransforms readStaticTransforms(MessageSource& bag, const std::string& topic)
{
    const auto& types = bag.topicTypes();
    const auto it = types.find(topic);
    if (it == types.end())
    {
        std::string list;
        for (const auto& [t, type] : types)
            if (type == types::kTFMessage) list += (list.empty() ? "" : ", ") + t;
        throw InputError(bag.path(), "has no topic " + topic + " (its " + types::kTFMessage +
                                         " topics: " + (list.empty() ? "none" : list) + ")");
    }
    core::require(it->second == types::kTFMessage, bag.path(),
                  "topic " + topic + " holds " + it->second + " messages, not " + types::kTFMessage);
    StaticTransforms tf;
    bag.read({topic}, [&](const BagMessage& m) {
        for (const TransformMsg& t : m.transforms()) tf.add(t);
        return true;
    });
    core::require(!tf.empty(), bag.path(), "topic " + topic + " holds no transform");
    return tf;
}

}  // namespace quasiloc::ros
