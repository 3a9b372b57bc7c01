#pragma once
// One rosbag2 SQLite3 storage file (.db3), read with Debian's libsqlite3: the `topics` table (id, name, type,
// serialization_format; the newer columns are not needed, so every schema from Crystal to today reads) and the
// `messages` table (topic_id, timestamp, data), read in timestamp order.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

struct sqlite3;

namespace quasiloc::ros
{
class SqliteBagFile
{
   public:
    struct Topic
    {
        std::int64_t id = 0;
        std::string name, type, serialization_format;
    };
    struct Message
    {
        const Topic* topic = nullptr;
        std::int64_t timestamp_ns = 0;  ///< the recorder's receive time
        const std::uint8_t* data = nullptr;
        std::size_t size = 0;
    };

    /** Opens read-only; not a SQLite database or without the rosbag2 tables is an InputError naming the file. */
    explicit SqliteBagFile(std::string path);
    ~SqliteBagFile();
    SqliteBagFile(const SqliteBagFile&) = delete;
    SqliteBagFile& operator=(const SqliteBagFile&) = delete;

    const std::string& path() const { return path_; }
    const std::vector<Topic>& topics() const { return topics_; }
    /** The messages of the named topics (all topics when empty) in timestamp order (then row order); visit
     *  returns false to stop. */
    void read(const std::vector<std::string>& topic_names, const std::function<bool(const Message&)>& visit) const;
    /** The number of messages per topic id. */
    std::vector<std::pair<std::int64_t, std::int64_t>> messageCounts() const;

   private:
    void open(bool immutable);
    void close();
    void fail(const std::string& what) const;

    std::string path_;
    sqlite3* db_ = nullptr;
    std::vector<Topic> topics_;
};

}  // namespace quasiloc::ros
