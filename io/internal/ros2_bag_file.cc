#include "io/internal/ros2_bag_file.h"

#include <lz4frame.h>
#include <sqlite3.h>
#include <yaml-cpp/yaml.h>
#include <zstd.h>

#include <algorithm>
#include <bit>
#include <boost/crc.hpp>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <stdexcept>

#include "io/internal/cdr.h"

namespace splam::io::internal {
namespace {

constexpr std::string_view kMcapMagic("\x89MCAP0\r\n", 8);
constexpr char kLaserScan2[] = "sensor_msgs/msg/LaserScan";
constexpr char kOdometry2[] = "nav_msgs/msg/Odometry";
constexpr char kTfMessage2[] = "tf2_msgs/msg/TFMessage";
// No chunk may claim more than this when decompressed, nor much more than 1000 times its
// compressed size (a few bytes claiming gigabytes would take the memory).
constexpr std::uint64_t kMaxChunkBytes = std::uint64_t{1} << 30;

[[noreturn]] void Fail(const std::string& message) { throw std::runtime_error(message); }

// Little-endian fields of an MCAP record, bounds-checked.
class Cursor {
 public:
  explicit Cursor(std::string_view bytes) : bytes_(bytes) {}
  std::size_t remaining() const { return bytes_.size() - at_; }
  std::string_view Take(std::uint64_t n, const char* what) {
    if (n > remaining()) Fail(std::string(what) + " runs past the end of its record");
    const std::string_view out = bytes_.substr(at_, n);
    at_ += n;
    return out;
  }
  template <class T>
  T Read(const char* what) {
    const std::string_view raw = Take(sizeof(T), what);
    unsigned char bytes[sizeof(T)];
    std::memcpy(bytes, raw.data(), sizeof(T));
    if (std::endian::native != std::endian::little) std::reverse(bytes, bytes + sizeof(T));
    T value;
    std::memcpy(&value, bytes, sizeof(T));
    return value;
  }
  std::string String(const char* what) {
    return std::string(Take(Read<std::uint32_t>(what), what));
  }

 private:
  std::string_view bytes_;
  std::size_t at_ = 0;
};

std::uint32_t Crc32(std::string_view bytes) {
  boost::crc_32_type crc;
  crc.process_bytes(bytes.data(), bytes.size());
  return crc.checksum();
}

std::string Decompress(std::string_view compression, std::string_view data, std::uint64_t size) {
  if (compression.empty()) {
    if (data.size() != size) Fail("an uncompressed chunk's size differs from its records'");
    return std::string(data);
  }
  if (size > kMaxChunkBytes || size > 1000 * static_cast<std::uint64_t>(data.size()) + (1 << 20))
    Fail("a chunk claims " + std::to_string(size) + " bytes from " + std::to_string(data.size()));
  std::string out(size, '\0');
  if (compression == "zstd") {
    const std::size_t n = ZSTD_decompress(out.data(), out.size(), data.data(), data.size());
    if (ZSTD_isError(n) || n != size)
      Fail(std::string("a zstd chunk does not decompress: ") +
           (ZSTD_isError(n) ? ZSTD_getErrorName(n) : "wrong size"));
    return out;
  }
  if (compression == "lz4") {
    LZ4F_dctx* context = nullptr;
    if (LZ4F_isError(LZ4F_createDecompressionContext(&context, LZ4F_VERSION)))
      Fail("lz4: no decompression context");
    const std::unique_ptr<LZ4F_dctx, decltype(&LZ4F_freeDecompressionContext)> owned(
        context, &LZ4F_freeDecompressionContext);
    std::size_t written = 0, read = 0;
    while (read < data.size()) {
      std::size_t out_size = out.size() - written, in_size = data.size() - read;
      const std::size_t hint = LZ4F_decompress(context, out.data() + written, &out_size,
                                               data.data() + read, &in_size, nullptr);
      if (LZ4F_isError(hint))
        Fail(std::string("an lz4 chunk does not decompress: ") + LZ4F_getErrorName(hint));
      written += out_size;
      read += in_size;
      if (hint == 0) break;
      if (in_size == 0 && out_size == 0) Fail("an lz4 chunk does not decompress: no progress");
    }
    if (written != size) Fail("an lz4 chunk decompresses to another size than it claims");
    return out;
  }
  Fail("chunk compression '" + std::string(compression) +
       "' is not supported (known: none, zstd, "
       "lz4)");
}

// MCAP records (opcode, uint64 length, content) of `bytes`, those that matter into *content.
struct McapState {
  std::map<std::uint16_t, std::string> schemas;  // id -> name
  std::map<std::uint16_t, int> channels;         // id -> index into content->topics
  Ros2Content* content;
};

void ParseRecords(std::string_view bytes, McapState* state, bool in_chunk) {
  Cursor c(bytes);
  while (c.remaining() > 0) {
    const auto opcode = c.Read<std::uint8_t>("a record's opcode");
    Cursor r(c.Take(c.Read<std::uint64_t>("a record's length"), "a record"));
    switch (opcode) {
      case 0x02:  // Footer: the end of the data
        if (!in_chunk) return;
        break;
      case 0x03: {  // Schema
        const auto id = r.Read<std::uint16_t>("a schema's id");
        state->schemas[id] = r.String("a schema's name");
        break;
      }
      case 0x04: {  // Channel
        const auto id = r.Read<std::uint16_t>("a channel's id");
        const auto schema = r.Read<std::uint16_t>("a channel's schema");
        Ros2Topic topic;
        topic.name = r.String("a channel's topic");
        topic.encoding = r.String("a channel's message encoding");
        const auto found = state->schemas.find(schema);
        topic.type = found != state->schemas.end() ? found->second : "";
        if (state->channels.contains(id)) break;  // repeated
        state->channels[id] = static_cast<int>(state->content->topics.size());
        state->content->topics.push_back(std::move(topic));
        break;
      }
      case 0x05: {  // Message
        const auto channel = r.Read<std::uint16_t>("a message's channel");
        r.Read<std::uint32_t>("a message's sequence");
        const auto log_time = r.Read<std::uint64_t>("a message's log time");
        r.Read<std::uint64_t>("a message's publish time");
        const auto found = state->channels.find(channel);
        if (found == state->channels.end())
          Fail("a message on channel " + std::to_string(channel) + ", which no record defines");
        state->content->messages.push_back(
            {found->second, static_cast<std::int64_t>(log_time & 0x7fffffffffffffff),
             std::string(r.Take(r.remaining(), "a message"))});
        break;
      }
      case 0x06: {  // Chunk
        if (in_chunk) Fail("a chunk inside a chunk");
        r.Read<std::uint64_t>("a chunk's start time");
        r.Read<std::uint64_t>("a chunk's end time");
        const auto size = r.Read<std::uint64_t>("a chunk's size");
        const auto crc = r.Read<std::uint32_t>("a chunk's CRC");
        const std::string compression = r.String("a chunk's compression");
        const std::string_view records =
            r.Take(r.Read<std::uint64_t>("a chunk's records"), "a chunk's records");
        const std::string plain = Decompress(compression, records, size);
        if (crc != 0 && Crc32(plain) != crc) Fail("a chunk's CRC does not match its records");
        ParseRecords(plain, state, true);
        break;
      }
      default:  // indexes, statistics, attachments, metadata: not needed
        break;
    }
  }
}

std::string ReadFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) Fail("cannot open " + path);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  return bytes;
}

// SQLite3 storage: the tables `topics` (id, name, type, serialization_format) and `messages`
// (topic_id, timestamp, data), appended to *content.
void ReadSqlite(const std::string& path, Ros2Content* content) {
  sqlite3* raw = nullptr;
  const int opened = sqlite3_open_v2(path.c_str(), &raw, SQLITE_OPEN_READONLY, nullptr);
  const std::unique_ptr<sqlite3, decltype(&sqlite3_close)> db(raw, &sqlite3_close);
  if (opened != SQLITE_OK) Fail(std::string("not an SQLite3 database: ") + sqlite3_errstr(opened));
  const auto query = [&](const char* sql, const auto& row) {
    sqlite3_stmt* statement = nullptr;
    if (sqlite3_prepare_v2(db.get(), sql, -1, &statement, nullptr) != SQLITE_OK)
      Fail(std::string("not a rosbag2 database: ") + sqlite3_errmsg(db.get()));
    const std::unique_ptr<sqlite3_stmt, decltype(&sqlite3_finalize)> owned(statement,
                                                                           &sqlite3_finalize);
    int step;
    while ((step = sqlite3_step(statement)) == SQLITE_ROW) row(statement);
    if (step != SQLITE_DONE)
      Fail(std::string("cannot read the database: ") + sqlite3_errmsg(db.get()));
  };
  const auto text = [](sqlite3_stmt* s, int column) {
    const unsigned char* t = sqlite3_column_text(s, column);
    return t != nullptr ? std::string(reinterpret_cast<const char*>(t)) : std::string();
  };
  std::map<sqlite3_int64, int> topic_of;
  query("SELECT id, name, type, serialization_format FROM topics", [&](sqlite3_stmt* s) {
    topic_of[sqlite3_column_int64(s, 0)] = static_cast<int>(content->topics.size());
    content->topics.push_back({text(s, 1), text(s, 2), text(s, 3)});
  });
  query("SELECT topic_id, timestamp, data FROM messages ORDER BY timestamp, id",
        [&](sqlite3_stmt* s) {
          const auto found = topic_of.find(sqlite3_column_int64(s, 0));
          if (found == topic_of.end()) Fail("a message of a topic the topics table does not hold");
          const auto* data = static_cast<const char*>(sqlite3_column_blob(s, 2));
          const int size = sqlite3_column_bytes(s, 2);
          content->messages.push_back({found->second, sqlite3_column_int64(s, 1),
                                       data != nullptr ? std::string(data, size) : std::string()});
        });
}

void ReadStorage(const std::string& path, Ros2Content* content) {
  if (path.ends_with(".db3")) return ReadSqlite(path, content);
  if (path.ends_with(".mcap")) {
    Ros2Content part = ParseMcap(ReadFile(path));
    const int offset = static_cast<int>(content->topics.size());
    for (Ros2Message& m : part.messages) m.topic += offset;
    content->topics.insert(content->topics.end(), part.topics.begin(), part.topics.end());
    content->messages.insert(content->messages.end(),
                             std::make_move_iterator(part.messages.begin()),
                             std::make_move_iterator(part.messages.end()));
    return;
  }
  Fail("storage file " + path + " is neither .db3 nor .mcap");
}

// The storage files a bag directory's metadata.yaml lists.
std::vector<std::string> DirectoryFiles(const std::string& dir) {
  const std::string metadata = (std::filesystem::path(dir) / "metadata.yaml").string();
  YAML::Node info;
  try {
    info = YAML::LoadFile(metadata)["rosbag2_bagfile_information"];
  } catch (const YAML::Exception& e) {
    Fail(metadata + ": " + e.what());
  }
  if (!info || !info.IsMap()) Fail(metadata + ": no rosbag2_bagfile_information");
  const YAML::Node compression = info["compression_format"];
  if (compression && compression.IsScalar() && !compression.Scalar().empty())
    Fail(metadata + ": files compressed with " + compression.Scalar() +
         " are not supported (decompress them with `ros2 bag convert`; compressed MCAP chunks "
         "are read)");
  const YAML::Node files = info["relative_file_paths"];
  if (!files || !files.IsSequence() || files.size() == 0)
    Fail(metadata + ": no relative_file_paths");
  std::vector<std::string> out;
  for (const YAML::Node& f : files) {
    if (!f.IsScalar()) Fail(metadata + ": relative_file_paths holds a non-string");
    out.push_back((std::filesystem::path(dir) / f.Scalar()).string());
  }
  return out;
}

// "sensor_msgs/msg/LaserScan" -> "sensor_msgs/LaserScan", as ROS 1 and RosBagTopics name it.
std::string Ros1Name(const std::string& type) {
  const std::size_t at = type.find("/msg/");
  return at == std::string::npos ? type : type.substr(0, at) + type.substr(at + 4);
}

// Writers of the two storages: topics registered as met, messages appended.
class Ros2Writer {
 public:
  virtual ~Ros2Writer() = default;
  virtual int Topic(const std::string& name, const std::string& type, const char* definition) = 0;
  virtual void Message(int topic, std::int64_t time_ns, const std::string& cdr) = 0;
  virtual void Close() = 0;
};

void AppendLe(std::string* out, std::uint64_t value, int bytes) {
  for (int i = 0; i < bytes; ++i) out->push_back(static_cast<char>((value >> (8 * i)) & 0xff));
}
void AppendString(std::string* out, const std::string& s) {
  AppendLe(out, s.size(), 4);
  *out += s;
}
void AppendRecord(std::string* out, std::uint8_t opcode, const std::string& content) {
  out->push_back(static_cast<char>(opcode));
  AppendLe(out, content.size(), 8);
  *out += content;
}

class McapWriter : public Ros2Writer {
 public:
  explicit McapWriter(std::string path) : path_(std::move(path)) {
    out_ = std::string(kMcapMagic);
    std::string header;
    AppendString(&header, "ros2");
    AppendString(&header, "splam");
    AppendRecord(&out_, 0x01, header);
  }
  int Topic(const std::string& name, const std::string& type, const char* definition) override {
    const auto id = static_cast<std::uint16_t>(++topics_);
    std::string schema;
    AppendLe(&schema, id, 2);
    AppendString(&schema, type);
    AppendString(&schema, "ros2msg");
    AppendString(&schema, definition);
    AppendRecord(&out_, 0x03, schema);
    std::string channel;
    AppendLe(&channel, id, 2);
    AppendLe(&channel, id, 2);
    AppendString(&channel, name);
    AppendString(&channel, "cdr");
    AppendLe(&channel, 0, 4);  // no metadata
    AppendRecord(&out_, 0x04, channel);
    return id;
  }
  void Message(int topic, std::int64_t time_ns, const std::string& cdr) override {
    std::string message;
    AppendLe(&message, static_cast<std::uint64_t>(topic), 2);
    AppendLe(&message, sequence_++, 4);
    AppendLe(&message, static_cast<std::uint64_t>(time_ns), 8);
    AppendLe(&message, static_cast<std::uint64_t>(time_ns), 8);
    message += cdr;
    if (chunk_.empty()) chunk_start_ = time_ns;
    chunk_end_ = time_ns;
    AppendRecord(&chunk_, 0x05, message);
    if (chunk_.size() >= (1 << 20)) Flush();
  }
  void Close() override {
    Flush();
    AppendRecord(&out_, 0x0f, std::string(4, '\0'));   // DataEnd, no CRC
    AppendRecord(&out_, 0x02, std::string(20, '\0'));  // Footer: no summary section
    out_ += kMcapMagic;
    std::ofstream file(path_, std::ios::binary);
    file.write(out_.data(), static_cast<std::streamsize>(out_.size()));
    file.close();
    if (!file) Fail("cannot write " + path_);
  }

 private:
  // The messages so far as one zstd-compressed chunk.
  void Flush() {
    if (chunk_.empty()) return;
    std::string compressed(ZSTD_compressBound(chunk_.size()), '\0');
    const std::size_t n =
        ZSTD_compress(compressed.data(), compressed.size(), chunk_.data(), chunk_.size(), 3);
    if (ZSTD_isError(n)) Fail(std::string("zstd: ") + ZSTD_getErrorName(n));
    compressed.resize(n);
    std::string record;
    AppendLe(&record, static_cast<std::uint64_t>(chunk_start_), 8);
    AppendLe(&record, static_cast<std::uint64_t>(chunk_end_), 8);
    AppendLe(&record, chunk_.size(), 8);
    AppendLe(&record, Crc32(chunk_), 4);
    AppendString(&record, "zstd");
    AppendLe(&record, compressed.size(), 8);
    record += compressed;
    AppendRecord(&out_, 0x06, record);
    chunk_.clear();
  }
  std::string path_, out_, chunk_;
  int topics_ = 0;
  std::uint32_t sequence_ = 0;
  std::int64_t chunk_start_ = 0, chunk_end_ = 0;
};

class SqliteWriter : public Ros2Writer {
 public:
  explicit SqliteWriter(const std::string& path) : db_(nullptr, &sqlite3_close) {
    std::error_code ec;
    std::filesystem::remove(path, ec);  // a new database, not rows added to an old one
    sqlite3* raw = nullptr;
    const int opened = sqlite3_open(path.c_str(), &raw);
    db_.reset(raw);
    if (opened != SQLITE_OK) Fail("cannot create " + path + ": " + sqlite3_errstr(opened));
    Execute(
        "PRAGMA journal_mode=MEMORY; BEGIN;"
        "CREATE TABLE schema(schema_version INTEGER PRIMARY KEY, ros_distro TEXT NOT NULL);"
        "INSERT INTO schema VALUES (3, 'humble');"
        "CREATE TABLE topics(id INTEGER PRIMARY KEY, name TEXT NOT NULL, type TEXT NOT NULL, "
        "serialization_format TEXT NOT NULL, offered_qos_profiles TEXT NOT NULL);"
        "CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id INTEGER NOT NULL, timestamp "
        "INTEGER NOT NULL, data BLOB NOT NULL);"
        "CREATE INDEX timestamp_idx ON messages (timestamp ASC);");
  }
  int Topic(const std::string& name, const std::string& type, const char* /*definition*/) override {
    const int id = ++topics_;
    Statement s(db_.get(), "INSERT INTO topics VALUES (?, ?, ?, 'cdr', '')");
    sqlite3_bind_int(s.get(), 1, id);
    sqlite3_bind_text(s.get(), 2, name.c_str(), -1, SQLITE_TRANSIENT);
    sqlite3_bind_text(s.get(), 3, type.c_str(), -1, SQLITE_TRANSIENT);
    s.Run();
    return id;
  }
  void Message(int topic, std::int64_t time_ns, const std::string& cdr) override {
    Statement s(db_.get(), "INSERT INTO messages (topic_id, timestamp, data) VALUES (?, ?, ?)");
    sqlite3_bind_int(s.get(), 1, topic);
    sqlite3_bind_int64(s.get(), 2, time_ns);
    sqlite3_bind_blob(s.get(), 3, cdr.data(), static_cast<int>(cdr.size()), SQLITE_TRANSIENT);
    s.Run();
  }
  void Close() override { Execute("COMMIT;"); }

 private:
  class Statement {
   public:
    Statement(sqlite3* db, const char* sql) : db_(db) {
      if (sqlite3_prepare_v2(db, sql, -1, &statement_, nullptr) != SQLITE_OK)
        Fail(std::string("sqlite: ") + sqlite3_errmsg(db));
    }
    ~Statement() { sqlite3_finalize(statement_); }
    sqlite3_stmt* get() const { return statement_; }
    void Run() {
      if (sqlite3_step(statement_) != SQLITE_DONE)
        Fail(std::string("sqlite: ") + sqlite3_errmsg(db_));
    }

   private:
    sqlite3* db_;
    sqlite3_stmt* statement_ = nullptr;
  };
  void Execute(const char* sql) {
    char* error = nullptr;
    if (sqlite3_exec(db_.get(), sql, nullptr, nullptr, &error) != SQLITE_OK) {
      const std::string message = error != nullptr ? error : "unknown error";
      sqlite3_free(error);
      Fail("sqlite: " + message);
    }
  }
  std::unique_ptr<sqlite3, decltype(&sqlite3_close)> db_;
  int topics_ = 0;
};

std::int64_t Nanoseconds(double t) { return std::llround(t * 1e9); }

}  // namespace

bool IsRos2BagPath(const std::string& path) {
  return path.ends_with(".db3") || path.ends_with(".mcap") ||
         (std::filesystem::is_directory(path) &&
          std::filesystem::exists(std::filesystem::path(path) / "metadata.yaml"));
}

Ros2Content ParseMcap(std::string_view bytes) {
  if (bytes.size() < 2 * kMcapMagic.size() || !bytes.starts_with(kMcapMagic))
    Fail("not an MCAP file (no MCAP magic at its start)");
  Ros2Content content;
  McapState state{{}, {}, &content};
  ParseRecords(bytes.substr(kMcapMagic.size()), &state, false);
  return content;
}

Ros2BagFile::Ros2BagFile(const std::string& path) {
  if (std::filesystem::is_directory(path)) {
    for (const std::string& file : DirectoryFiles(path)) ReadStorage(file, &content_);
  } else {
    ReadStorage(path, &content_);
  }
  std::stable_sort(
      content_.messages.begin(), content_.messages.end(),
      [](const Ros2Message& a, const Ros2Message& b) { return a.time_ns < b.time_ns; });
}

RosBagTopics Ros2BagFile::Topics() const {
  RosBagTopics topics;
  for (const Ros2Topic& t : content_.topics) {
    topics.types[t.name] = Ros1Name(t.type);
    topics.counts[t.name];
  }
  for (const Ros2Message& m : content_.messages)
    ++topics.counts[content_.topics[static_cast<std::size_t>(m.topic)].name];
  return topics;
}

RosBagMessages Ros2BagFile::Messages(const std::string& scan_topic, const std::string& odom_topic,
                                     const std::string& truth_topic, bool read_tf) const {
  RosBagMessages out;
  for (const Ros2Message& m : content_.messages) {
    const Ros2Topic& topic = content_.topics[static_cast<std::size_t>(m.topic)];
    const std::string& name = topic.name;
    const bool scan = name == scan_topic, odom = name == odom_topic, truth = name == truth_topic,
               tf = read_tf && name == "/tf", tf_static = name == "/tf_static";
    if (!scan && !odom && !truth && !tf && !tf_static) continue;
    if (topic.encoding != "cdr")
      Fail("topic " + name + " is serialized as '" + topic.encoding + "'; splam reads cdr");
    const auto fail = [&] {
      Fail("a message on " + name + " does not decode as " + topic.type + " (CDR)");
    };
    if (scan) {
      if (topic.type != kLaserScan2 || !DecodeLaserScan(m.data, &out.scans.emplace_back())) fail();
    } else if (odom || truth) {
      RosPose p;
      if (topic.type != kOdometry2 || !DecodeOdometry(m.data, &p)) fail();
      (odom ? out.odometry : out.truth).push_back(std::move(p));
    } else if (topic.type != kTfMessage2 ||
               !DecodeTransforms(m.data, tf ? &out.tf : &out.tf_static)) {
      fail();
    }
  }
  return out;
}

void WriteRos2Bag(const std::string& path, Ros2Storage storage, const std::string& scan_topic,
                  const std::string& odom_topic, const std::string& truth_topic,
                  const RosBagMessages& messages) {
  std::unique_ptr<Ros2Writer> writer;
  if (storage == Ros2Storage::kMcap)
    writer = std::make_unique<McapWriter>(path);
  else
    writer = std::make_unique<SqliteWriter>(path);
  // Every message with its topic and time, in time order.
  struct Out {
    std::int64_t time_ns;
    int topic;
    std::string cdr;
  };
  std::vector<Out> out;
  const int tf_static = messages.tf_static.empty()
                            ? 0
                            : writer->Topic("/tf_static", kTfMessage2, kTfMessageDefinition);
  if (tf_static != 0)
    out.push_back({Nanoseconds(messages.tf_static.front().time_s), tf_static,
                   EncodeTransforms(messages.tf_static)});
  const int tf = messages.tf.empty() ? 0 : writer->Topic("/tf", kTfMessage2, kTfMessageDefinition);
  for (const RosPose& p : messages.tf)
    out.push_back({Nanoseconds(p.time_s), tf, EncodeTransforms({p})});
  const int odom =
      messages.odometry.empty() ? 0 : writer->Topic(odom_topic, kOdometry2, kOdometryDefinition);
  for (const RosPose& p : messages.odometry)
    out.push_back({Nanoseconds(p.time_s), odom, EncodeOdometry(p)});
  const int truth =
      messages.truth.empty() ? 0 : writer->Topic(truth_topic, kOdometry2, kOdometryDefinition);
  for (const RosPose& p : messages.truth)
    out.push_back({Nanoseconds(p.time_s), truth, EncodeOdometry(p)});
  const int scan =
      messages.scans.empty() ? 0 : writer->Topic(scan_topic, kLaserScan2, kLaserScanDefinition);
  for (const RosScan& s : messages.scans)
    out.push_back({Nanoseconds(s.time_s), scan, EncodeLaserScan(s)});
  std::stable_sort(out.begin(), out.end(),
                   [](const Out& a, const Out& b) { return a.time_ns < b.time_ns; });
  for (const Out& o : out) writer->Message(o.topic, o.time_ns, o.cdr);
  writer->Close();
}

}  // namespace splam::io::internal
