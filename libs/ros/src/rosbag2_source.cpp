// ROS 2 bags as a MessageSource (rosbag2_source.h).
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <quasiloc/core/error.h>
#include <quasiloc/ros/cdr.h>
#include <quasiloc/ros/compression.h>
#include <quasiloc/ros/mcap_reader.h>
#include <quasiloc/ros/point_cloud2.h>
#include <quasiloc/ros/rosbag2_metadata.h>
#include <quasiloc/ros/rosbag2_source.h>
#include <quasiloc/ros/sqlite_bag.h>

namespace fs = std::filesystem;
using quasiloc::core::InputError;

namespace quasiloc::ros
{
namespace
{
constexpr std::size_t kMaxMessageBytes = std::size_t(512) << 20;  ///< a decompressed message: 512 MB at most

std::string lower(std::string s)
{
    for (auto& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

bool endsWith(const std::string& s, const std::string& tail)
{
    return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

/** A CDR message of a ROS 2 bag. */
class CdrMessage : public BagMessage
{
   public:
    CdrMessage(const std::string& file, const std::string& topic, const std::string& type, const std::string& format,
               std::int64_t t_ns, const std::uint8_t* data, std::size_t size, bool zstd_compressed)
        : file_(file), topic_(topic), type_(type), format_(format), t_ns_(t_ns), data_(data), size_(size)
    {
        if (zstd_compressed)
        {
            owned_ = zstdDecompress(data, size, kMaxMessageBytes, where() + " (zstd-compressed message)");
            data_ = owned_.data();
            size_ = owned_.size();
        }
    }
    const std::string& topic() const override { return topic_; }
    const std::string& type() const override { return type_; }
    std::int64_t timeNs() const override { return t_ns_; }
    std::vector<std::uint8_t> payload() const override { return {data_, data_ + size_}; }

    ImageMsg image() const override { return cdr::readImage(*reader(types::kImage)); }
    CompressedImageMsg compressedImage() const override
    {
        return cdr::readCompressedImage(*reader(types::kCompressedImage));
    }
    ImuMsg imu() const override { return cdr::readImu(*reader(types::kImu)); }
    CameraInfoMsg cameraInfo() const override { return cdr::readCameraInfo(*reader(types::kCameraInfo)); }
    PoseMsg pose() const override
    {
        if (type_ == types::kPoseStamped) return cdr::readPoseStamped(*reader(types::kPoseStamped));
        if (type_ == types::kOdometry) return cdr::readOdometry(*reader(types::kOdometry));
        const TransformMsg t = cdr::readTransformStamped(*reader(types::kTransformStamped));
        return PoseMsg{t.header, t.translation, t.rotation};
    }
    std::vector<TransformMsg> transforms() const override { return cdr::readTFMessage(*reader(types::kTFMessage)); }
    PointCloud2Msg pointCloud2() const override { return cdr::readPointCloud2(*reader(types::kPointCloud2)); }

   protected:
    const std::string& file() const override { return file_; }

   private:
    std::unique_ptr<cdr::Reader> reader(const char* expected) const
    {
        if (type_ != expected)
            throw InputError(where(), "message type " + type_ + " where " + expected + " is expected");
        if (format_ != "cdr")
            throw InputError(where(), "serialization format '" + format_ + "' is not supported (cdr is)");
        return std::make_unique<cdr::Reader>(data_, size_, where());
    }

    const std::string& file_;
    const std::string& topic_;
    const std::string& type_;
    const std::string& format_;
    std::int64_t t_ns_;
    const std::uint8_t* data_;
    std::size_t size_;
    std::vector<std::uint8_t> owned_;
};

/** A folder of this process's decompressed storage files, removed with it. */
class TempFolder
{
   public:
    const std::string& path()
    {
        if (path_.empty())
        {
            static std::atomic<int> counter{0};
            path_ = (fs::temp_directory_path() /
                     ("quasiloc-bag-" + std::to_string(::getpid()) + "-" + std::to_string(counter++)))
                        .string();
            fs::create_directories(path_);
        }
        return path_;
    }
    ~TempFolder()
    {
        std::error_code ec;
        if (!path_.empty()) fs::remove_all(path_, ec);
    }

   private:
    std::string path_;
};

struct TopicInfo
{
    std::string type, format;  ///< normalised type, serialization format
};

class Rosbag2Source : public MessageSource
{
   public:
    explicit Rosbag2Source(const std::string& path) : path_(path)
    {
        locateFiles();
        for (const auto& f : files_) bytes_ += fs::file_size(f.original);
        for (auto& f : files_) openFile(f);
    }

    const std::string& path() const override { return path_; }
    std::string describe() const override
    {
        return "rosbag2 " + storage_ + (files_.size() > 1 ? " (" + std::to_string(files_.size()) + " files)" : "") +
               (message_zstd_ ? ", zstd messages" : "") + (file_zstd_ ? ", zstd files" : "");
    }
    std::uint64_t bytes() const override { return bytes_; }
    const std::map<std::string, std::string>& topicTypes() const override { return types_; }
    std::pair<std::int64_t, std::int64_t> timeSpanNs() const override { return span_; }

    void read(const std::vector<std::string>& topics, const std::function<bool(const BagMessage&)>& visit) override
    {
        for (auto& f : files_)
        {
            bool go_on = true;
            if (f.sqlite)
                f.sqlite->read(topics, [&](const SqliteBagFile::Message& m) {
                    const TopicInfo& info = topics_.at(m.topic->name);
                    const CdrMessage msg(f.original, m.topic->name, info.type, info.format, m.timestamp_ns, m.data,
                                         m.size, message_zstd_);
                    return go_on = visit(msg);
                });
            else
                f.mcap->readMessages([&](const mcap::MessageView& m) {
                    const std::string& topic = m.channel->topic;
                    if (std::find(topics.begin(), topics.end(), topic) == topics.end() && !topics.empty()) return true;
                    const auto it = topics_.find(topic);
                    if (it == topics_.end())
                        throw InputError(f.original, "topic " + topic + " has a channel that the summary lacks");
                    const TopicInfo& info = it->second;
                    const CdrMessage msg(f.original, topic, info.type, info.format, std::int64_t(m.log_time), m.data,
                                         m.size, message_zstd_);
                    return go_on = visit(msg);
                });
            if (!go_on) return;
        }
    }

   private:
    struct File
    {
        std::string original, readable;  ///< the bag's file; the file read (a decompressed copy in file mode)
        std::unique_ptr<SqliteBagFile> sqlite;
        std::unique_ptr<mcap::Reader> mcap;
    };

    void locateFiles()
    {
        std::error_code ec;
        if (fs::is_regular_file(path_, ec))
        {
            if (endsWith(path_, ".zstd"))  // one file of a bag recorded with file compression
            {
                file_zstd_ = true;
                storage_ = endsWith(path_, ".mcap.zstd") ? "mcap" : "sqlite3";
            }
            else
                storage_ = storageOfFile(path_, path_);
            files_.push_back({path_, path_, nullptr, nullptr});
            return;
        }
        if (!fs::is_directory(path_, ec)) throw InputError(path_, "bag not found (a rosbag2 folder, .db3 or .mcap)");
        const std::string yaml = (fs::path(path_) / "metadata.yaml").string();
        if (!fs::is_regular_file(yaml, ec))
            throw InputError(path_,
                             "a folder without metadata.yaml: not a rosbag2 bag (give the folder rosbag2 "
                             "wrote, or one .db3 / .mcap file)");
        const Rosbag2Metadata m = readRosbag2Metadata(yaml);
        storage_ = m.storage_identifier;
        if (storage_ != "sqlite3" && storage_ != "mcap")
            throw InputError(yaml, "storage_identifier '" + storage_ + "' is not supported (sqlite3 or mcap)");
        const std::string mode = lower(m.compression_mode);
        if (!mode.empty() && mode != "none")
        {
            if (m.compression_format != "zstd")
                throw InputError(yaml, "compression_format '" + m.compression_format +
                                           "' is not supported (zstd, the only one rosbag2 ships)");
            if (mode == "message")
                message_zstd_ = true;
            else if (mode == "file")
                file_zstd_ = true;
            else
                throw InputError(yaml,
                                 "compression_mode '" + m.compression_mode + "' is not supported (file, message)");
        }
        for (const auto& rel : m.relative_file_paths)
        {
            // rosbag2 before Foxy wrote paths that start with the bag folder's own name.
            fs::path p = fs::path(path_) / rel;
            if (!fs::is_regular_file(p, ec)) p = fs::path(path_).parent_path() / rel;
            if (!fs::is_regular_file(p, ec))
                throw InputError(yaml, "names storage file '" + rel + "', which is not in " + path_);
            files_.push_back({p.string(), p.string(), nullptr, nullptr});
        }
        if (m.duration_ns > 0) span_ = {m.starting_time_ns, m.starting_time_ns + m.duration_ns};
    }

    static std::string storageOfFile(const std::string& file, const std::string& named)
    {
        char head[16] = {};
        std::ifstream(file, std::ios::binary).read(head, sizeof head);
        if (std::equal(std::begin(mcap::kMagic), std::end(mcap::kMagic), reinterpret_cast<std::uint8_t*>(head)))
            return "mcap";
        if (std::string(head, 15) == "SQLite format 3") return "sqlite3";
        if (endsWith(file, ".mcap")) return "mcap";  // the reader will say what is wrong with it
        if (endsWith(file, ".db3")) return "sqlite3";
        throw InputError(named,
                         "unknown storage: neither an MCAP nor a SQLite3 file (a rosbag2 folder, .db3 or .mcap)");
    }

    void openFile(File& f)
    {
        if (file_zstd_ || endsWith(f.original, ".zstd"))
        {
            file_zstd_ = true;
            const std::string name = fs::path(f.original).stem().string();
            f.readable = (fs::path(temp_.path()) / name).string();
            zstdDecompressFile(f.original, f.readable);
        }
        const std::string kind = storageOfFile(f.readable, f.original);
        if (kind != storage_) throw InputError(f.original, "is a " + kind + " file, the bag's storage is " + storage_);
        try
        {
            if (kind == "sqlite3")
            {
                f.sqlite = std::make_unique<SqliteBagFile>(f.readable);
                for (const auto& t : f.sqlite->topics()) addTopic(t.name, t.type, t.serialization_format, f);
            }
            else
            {
                f.mcap = std::make_unique<mcap::Reader>(f.readable);
                if (!f.mcap->summary().present) f.mcap->readMessages([](const mcap::MessageView&) { return true; });
                for (const auto& [id, c] : f.mcap->channels())
                    addTopic(c.topic, f.mcap->typeOf(c), c.message_encoding, f);
            }
        }
        catch (const InputError& e)
        {
            if (f.readable == f.original) throw;
            throw InputError(f.original, std::string("(decompressed) ") + e.what());
        }
    }

    void addTopic(const std::string& name, const std::string& type, const std::string& format, const File& f)
    {
        const TopicInfo info{normalisedTypeName(type), format};
        const auto [it, added] = topics_.emplace(name, info);
        if (!added && it->second.type != info.type)
            throw InputError(f.original, "topic " + name + " holds " + type + " here and " + it->second.type +
                                             " in an earlier file of the bag");
        types_[name] = info.type;
    }

    std::string path_, storage_;
    TempFolder temp_;  // declared before files_: the readers close before their files are removed
    std::vector<File> files_;
    std::map<std::string, TopicInfo> topics_;
    std::map<std::string, std::string> types_;
    std::uint64_t bytes_ = 0;
    std::pair<std::int64_t, std::int64_t> span_{0, 0};
    bool message_zstd_ = false, file_zstd_ = false;
};
}  // namespace

std::unique_ptr<MessageSource> openRosbag2(const std::string& path) { return std::make_unique<Rosbag2Source>(path); }

}  // namespace quasiloc::ros
