// rosbag2 SQLite3 storage file (sqlite_bag.h).
#include <sqlite3.h>

#include <filesystem>
#include <memory>
#include <quasiloc/core/error.h>
#include <quasiloc/ros/sqlite_bag.h>

using quasiloc::core::InputError;

namespace quasiloc::ros
{
namespace
{
using Statement = std::unique_ptr<sqlite3_stmt, decltype(&sqlite3_finalize)>;

std::string uriOf(const std::string& path, bool immutable)
{
    // A URI so that the database is opened read-only; "immutable" also skips the locking and the -wal / -shm files
    // (a bag on a read-only medium, or whose folder we may not write).
    std::string uri = "file:";
    for (char c : std::filesystem::absolute(path).string())
    {
        if (c == '%' || c == '?' || c == '#')
        {
            char hex[4];
            std::snprintf(hex, sizeof hex, "%%%02X", unsigned(static_cast<unsigned char>(c)));
            uri += hex;
        }
        else
            uri += c;
    }
    return uri + (immutable ? "?mode=ro&immutable=1" : "?mode=ro");
}
}  // namespace

SqliteBagFile::SqliteBagFile(std::string path) : path_(std::move(path))
{
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path_, ec)) throw InputError(path_, "SQLite3 bag file not found");
    try
    {
        open(false);
    }
    catch (const InputError&)
    {
        // A read-only folder with a leftover -wal / -shm file cannot be opened with locking: read it as immutable.
        close();
        try
        {
            open(true);
        }
        catch (const InputError&)
        {
            close();  // the destructor does not run when the constructor throws
            throw;
        }
    }
}

void SqliteBagFile::close()
{
    if (db_) sqlite3_close(db_);
    db_ = nullptr;
    topics_.clear();
}

SqliteBagFile::~SqliteBagFile() { close(); }

void SqliteBagFile::fail(const std::string& what) const
{
    throw InputError(path_, what + ": " + (db_ ? sqlite3_errmsg(db_) : "no database") +
                                " (not a rosbag2 SQLite3 file, or a corrupt one)");
}

void SqliteBagFile::open(bool immutable)
{
    if (sqlite3_open_v2(uriOf(path_, immutable).c_str(), &db_, SQLITE_OPEN_READONLY | SQLITE_OPEN_URI, nullptr) !=
        SQLITE_OK)
        fail("cannot open as SQLite3");
    sqlite3_stmt* raw = nullptr;
    if (sqlite3_prepare_v2(db_, "SELECT id, name, type, serialization_format FROM topics ORDER BY id", -1, &raw,
                           nullptr) != SQLITE_OK)
        fail("cannot read the topics table");
    Statement st(raw, sqlite3_finalize);
    int rc;
    while ((rc = sqlite3_step(st.get())) == SQLITE_ROW)
    {
        Topic t;
        t.id = sqlite3_column_int64(st.get(), 0);
        const auto text = [&](int col) {
            const auto* p = sqlite3_column_text(st.get(), col);
            return p ? std::string(reinterpret_cast<const char*>(p)) : std::string();
        };
        t.name = text(1);
        t.type = text(2);
        t.serialization_format = text(3);
        topics_.push_back(std::move(t));
    }
    if (rc != SQLITE_DONE) fail("cannot read the topics table");
    // The messages table must be there too, with the columns read below.
    if (sqlite3_prepare_v2(db_, "SELECT topic_id, timestamp, data FROM messages LIMIT 0", -1, &raw, nullptr) !=
        SQLITE_OK)
        fail("cannot read the messages table");
    sqlite3_finalize(raw);
}

void SqliteBagFile::read(const std::vector<std::string>& topic_names,
                         const std::function<bool(const Message&)>& visit) const
{
    std::string ids;
    std::vector<const Topic*> by_index;
    for (const auto& t : topics_)
    {
        bool wanted = topic_names.empty();
        for (const auto& n : topic_names) wanted = wanted || n == t.name;
        if (!wanted) continue;
        ids += (ids.empty() ? "" : ",") + std::to_string(t.id);
    }
    if (ids.empty()) return;
    const std::string sql =
        "SELECT topic_id, timestamp, data FROM messages WHERE topic_id IN (" + ids + ") ORDER BY timestamp, id";
    sqlite3_stmt* raw = nullptr;
    if (sqlite3_prepare_v2(db_, sql.c_str(), -1, &raw, nullptr) != SQLITE_OK) fail("cannot read the messages");
    Statement st(raw, sqlite3_finalize);
    int rc;
    while ((rc = sqlite3_step(st.get())) == SQLITE_ROW)
    {
        Message m;
        const std::int64_t id = sqlite3_column_int64(st.get(), 0);
        for (const auto& t : topics_)
            if (t.id == id) m.topic = &t;
        if (!m.topic) continue;  // cannot happen: the query selects known ids
        m.timestamp_ns = sqlite3_column_int64(st.get(), 1);
        m.data = static_cast<const std::uint8_t*>(sqlite3_column_blob(st.get(), 2));
        m.size = std::size_t(sqlite3_column_bytes(st.get(), 2));
        if (!visit(m)) return;
    }
    if (rc != SQLITE_DONE) fail("cannot read the messages");
}

std::vector<std::pair<std::int64_t, std::int64_t>> SqliteBagFile::messageCounts() const
{
    sqlite3_stmt* raw = nullptr;
    if (sqlite3_prepare_v2(db_, "SELECT topic_id, COUNT(*) FROM messages GROUP BY topic_id", -1, &raw, nullptr) !=
        SQLITE_OK)
        fail("cannot count the messages");
    Statement st(raw, sqlite3_finalize);
    std::vector<std::pair<std::int64_t, std::int64_t>> counts;
    int rc;
    while ((rc = sqlite3_step(st.get())) == SQLITE_ROW)
        counts.emplace_back(sqlite3_column_int64(st.get(), 0), sqlite3_column_int64(st.get(), 1));
    if (rc != SQLITE_DONE) fail("cannot count the messages");
    return counts;
}

}  // namespace quasiloc::ros
