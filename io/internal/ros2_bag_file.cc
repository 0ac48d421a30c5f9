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
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <set>
#include <stdexcept>

#include "io/internal/cdr.h"

namespace splam::io::internal {
namespace {

constexpr std::string_view kMcapMagic("\x89MCAP0\r\n", 8);
constexpr char kLaserScan2[] = "sensor_msgs/msg/LaserScan";
constexpr char kOdometry2[] = "nav_msgs/msg/Odometry";
constexpr char kTfMessage2[] = "tf2_msgs/msg/TFMessage";
constexpr std::uint64_t kHeldBytesPerMessage = 256;
constexpr std::int64_t kMaxCount = std::numeric_limits<int>::max();
constexpr std::uint64_t kMaxMetadataBytes = std::uint64_t{16} << 20;
// The progress handler counts SQLite's virtual-machine steps this many at a time.
constexpr int kSqliteStepsPerCall = 10000;

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

// One pass over a bag's storage files: the topics as found (a topic's index is its place in that
// order), how many messages each holds, and the messages of the topics `wanted` chooses, handed
// to `take` (a view valid during the call). Only those are held; the others are counted.
struct Ros2Pass {
  explicit Ros2Pass(const Ros2ReadLimits& l) : limits(l) {}
  const Ros2ReadLimits& limits;
  std::function<bool(const Ros2Topic&)> wanted;  // empty: none (a pass that only counts)
  std::function<void(int topic, std::int64_t time_ns, std::string_view data)> take;
  std::vector<Ros2Topic> topics;
  std::vector<std::int64_t> counts;
  std::vector<char> taken;                 // per topic: whether its messages go to `take`
  std::uint64_t decompressed = 0;          // bytes of every chunk decompressed so far
  std::uint64_t decompression_budget = 0;  // bytes the pass may decompress

  int AddTopic(Ros2Topic topic) {
    if (topics.size() >= limits.max_topics)
      Fail("more than " + std::to_string(limits.max_topics) + " topics, the most a bag may have");
    taken.push_back(wanted && wanted(topic) ? 1 : 0);
    counts.push_back(0);
    topics.push_back(std::move(topic));
    return static_cast<int>(topics.size()) - 1;
  }
  void Message(int topic, std::int64_t time_ns, std::string_view data) {
    ++counts[static_cast<std::size_t>(topic)];
    if (taken[static_cast<std::size_t>(topic)]) take(topic, time_ns, data);
  }
};

// MCAP records (opcode, uint64 length, content) of a file or a chunk; those that matter go to
// the pass.
struct McapState {
  std::map<std::uint16_t, std::string> schemas;  // id -> name
  std::map<std::uint16_t, int> channels;         // id -> topic index of the pass
  Ros2Pass* pass;
};

void ParseRecords(std::string_view bytes, McapState* state);

void ParseRecord(std::uint8_t opcode, Cursor r, McapState* state, bool in_chunk) {
  switch (opcode) {
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
      if (state->channels.contains(id)) break;  // repeated (the summary section repeats them)
      state->channels[id] = state->pass->AddTopic(std::move(topic));
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
      if (r.remaining() > state->pass->limits.max_message_bytes)
        Fail("a message of " + std::to_string(r.remaining()) + " bytes (at most " +
             std::to_string(state->pass->limits.max_message_bytes) + ")");
      state->pass->Message(found->second, static_cast<std::int64_t>(log_time & 0x7fffffffffffffff),
                           r.Take(r.remaining(), "a message"));
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
      Ros2Pass& pass = *state->pass;
      if (size > pass.limits.max_chunk_bytes ||
          (!compression.empty() &&
           size > 1000 * static_cast<std::uint64_t>(records.size()) + (std::uint64_t{1} << 20)))
        Fail("a chunk claims " + std::to_string(size) + " bytes from " +
             std::to_string(records.size()) + " (at most " +
             std::to_string(pass.limits.max_chunk_bytes) + ", and 1000 times its compressed size)");
      pass.decompressed += size;
      if (pass.decompressed > pass.decompression_budget)
        Fail("its chunks decompress to more than " + std::to_string(pass.decompression_budget) +
             " bytes (" + std::to_string(pass.limits.max_decompressed_bytes) + " and " +
             std::to_string(pass.limits.decompression_ratio) +
             " times the size of its storage files), the most a bag may hold");
      const std::string plain = Decompress(compression, records, size);
      if (crc != 0 && Crc32(plain) != crc) Fail("a chunk's CRC does not match its records");
      ParseRecords(plain, state);
      break;
    }
    default:  // indexes, statistics, attachments, metadata: not needed
      break;
  }
}

// The records inside a chunk.
void ParseRecords(std::string_view bytes, McapState* state) {
  Cursor c(bytes);
  while (c.remaining() > 0) {
    const auto opcode = c.Read<std::uint8_t>("a record's opcode");
    ParseRecord(opcode, Cursor(c.Take(c.Read<std::uint64_t>("a record's length"), "a record")),
                state, true);
  }
}

// The size of `path` when it is a regular file (after links); else why it cannot be storage:
// a FIFO blocks for ever, a device (a link to /dev/zero) never ends.
std::uint64_t RegularFileSize(const std::string& path) {
  std::error_code error;
  const std::filesystem::file_status status = std::filesystem::status(path, error);
  if (error) Fail(path + ": " + error.message());
  if (status.type() != std::filesystem::file_type::regular)
    Fail(path + " is not a regular file (a directory, a FIFO or a device)");
  const std::uint64_t size = std::filesystem::file_size(path, error);
  if (error) Fail(path + ": " + error.message());
  return size;
}

// An MCAP file, record by record: only a chunk (at most max_chunk_bytes) or a small record is in
// memory at a time; the records splam does not read are skipped.
void ReadMcap(const std::string& path, std::uint64_t size, Ros2Pass* pass) {
  std::ifstream in(path, std::ios::binary);
  if (!in) Fail("cannot open " + path);
  const auto read = [&](std::uint64_t n, const char* what) {
    std::string bytes(n, '\0');
    if (!in.read(bytes.data(), static_cast<std::streamsize>(n)))
      Fail(std::string(what) + " runs past the end of the file");
    return bytes;
  };
  if (size < 2 * kMcapMagic.size() || read(kMcapMagic.size(), "the magic") != kMcapMagic)
    Fail("not an MCAP file (no MCAP magic at its start)");
  McapState state{{}, {}, pass};
  for (std::uint64_t at = kMcapMagic.size(); at < size;) {
    const std::string head = read(9, "a record's length");
    const auto opcode = static_cast<std::uint8_t>(head[0]);
    const auto length = Cursor(std::string_view(head).substr(1)).Read<std::uint64_t>("a length");
    at += 9;
    if (length > size - at) Fail("a record runs past the end of the file");
    if (opcode == 0x02) return;  // Footer: the end of the data
    const bool needed = opcode >= 0x03 && opcode <= 0x06;
    const std::uint64_t most =
        (opcode == 0x06 ? pass->limits.max_chunk_bytes : pass->limits.max_message_bytes) + 1024;
    if (needed && length > most)
      Fail("a record of " + std::to_string(length) + " bytes (at most " + std::to_string(most) +
           ")");
    if (needed) {
      const std::string record = read(length, "a record");
      ParseRecord(opcode, Cursor(record), &state, false);
    } else {
      in.seekg(static_cast<std::streamoff>(length), std::ios::cur);
    }
    at += length;
  }
}

// SQLite3 storage: the tables `topics` (id, name, type, serialization_format) and `messages`
// (topic_id, timestamp, data), read in the order of their ids. Tables only: a view (or a virtual
// table) over a recursive query never ends. Work and sizes are bounded: no value above
// max_message_bytes (SQLite's length limit), and at most sqlite_steps_per_byte virtual-machine
// steps per byte of the file (a table scan needs a few per row).
void ReadSqlite(const std::string& path, std::uint64_t size, Ros2Pass* pass) {
  // Immutable: SQLite then looks for no journal, WAL or lock beside the file (a FIFO named
  // X.db3-journal blocked the read for ever). The path as a URI: '%', '?', '#' and control bytes
  // percent-encoded.
  std::string uri = "file:";
  for (const char c : path) {
    const auto byte = static_cast<unsigned char>(c);
    if (byte < 0x20 || byte >= 0x7f || c == '%' || c == '?' || c == '#') {
      constexpr char kHex[] = "0123456789ABCDEF";
      uri += {'%', kHex[byte >> 4], kHex[byte & 0xf]};
    } else {
      uri += c;
    }
  }
  uri += "?immutable=1";
  sqlite3* raw = nullptr;
  const int opened =
      sqlite3_open_v2(uri.c_str(), &raw, SQLITE_OPEN_READONLY | SQLITE_OPEN_URI, nullptr);
  const std::unique_ptr<sqlite3, decltype(&sqlite3_close)> db(raw, &sqlite3_close);
  if (opened != SQLITE_OK) Fail(std::string("not an SQLite3 database: ") + sqlite3_errstr(opened));
  const Ros2ReadLimits& limits = pass->limits;
  sqlite3_limit(db.get(), SQLITE_LIMIT_LENGTH,
                static_cast<int>(std::min<std::uint64_t>(limits.max_message_bytes, 1u << 30)));
  struct Budget {
    std::uint64_t left;
  } budget{(size + (std::uint64_t{1} << 20)) * limits.sqlite_steps_per_byte / kSqliteStepsPerCall};
  sqlite3_progress_handler(
      db.get(), kSqliteStepsPerCall,
      [](void* b) { return static_cast<Budget*>(b)->left-- == 0 ? 1 : 0; }, &budget);
  const auto query = [&](const std::string& sql, const auto& row) {
    sqlite3_stmt* statement = nullptr;
    if (sqlite3_prepare_v2(db.get(), sql.c_str(), -1, &statement, nullptr) != SQLITE_OK)
      Fail(std::string("not a rosbag2 database: ") + sqlite3_errmsg(db.get()));
    const std::unique_ptr<sqlite3_stmt, decltype(&sqlite3_finalize)> owned(statement,
                                                                           &sqlite3_finalize);
    int step;
    while ((step = sqlite3_step(statement)) == SQLITE_ROW) row(statement);
    if (step == SQLITE_INTERRUPT)
      Fail("reading the database takes more than " + std::to_string(limits.sqlite_steps_per_byte) +
           " steps per byte of the file (a damaged or hostile database)");
    if (step != SQLITE_DONE)
      Fail(std::string("cannot read the database: ") + sqlite3_errmsg(db.get()));
  };
  const auto text = [](sqlite3_stmt* s, int column) {
    const unsigned char* t = sqlite3_column_text(s, column);
    return t != nullptr ? std::string(reinterpret_cast<const char*>(t)) : std::string();
  };
  std::map<std::string, std::string> kinds;  // table name -> how it is defined
  query("SELECT name, type, sql FROM sqlite_master WHERE name IN ('topics', 'messages')",
        [&](sqlite3_stmt* s) {
          const std::string type = text(s, 1);
          kinds[text(s, 0)] =
              type == "table" && text(s, 2).starts_with("CREATE VIRTUAL") ? "virtual table" : type;
        });
  for (const char* table : {"topics", "messages"}) {
    const auto kind = kinds.find(table);
    if (kind == kinds.end()) Fail(std::string("not a rosbag2 database: no such table: ") + table);
    if (kind->second != "table")
      Fail(std::string("not a rosbag2 database: `") + table + "` is a " + kind->second +
           ", not a table (rosbag2 writes tables)");
  }
  std::map<sqlite3_int64, int> topic_of;
  std::string taken;  // ids of the topics whose messages are read, "1, 3"
  query("SELECT id, name, type, serialization_format FROM topics", [&](sqlite3_stmt* s) {
    const sqlite3_int64 id = sqlite3_column_int64(s, 0);
    if (topic_of.contains(id)) return;
    const int index = pass->AddTopic({text(s, 1), text(s, 2), text(s, 3)});
    topic_of[id] = index;
    if (pass->taken[static_cast<std::size_t>(index)])
      taken += (taken.empty() ? "" : ", ") + std::to_string(id);
  });
  const auto topic = [&](sqlite3_stmt* s) {
    const auto found = topic_of.find(sqlite3_column_int64(s, 0));
    if (found == topic_of.end()) Fail("a message of a topic the topics table does not hold");
    return found->second;
  };
  // Counted without reading the data (SQLite stops decoding a row at the last column asked for).
  query("SELECT topic_id FROM messages", [&](sqlite3_stmt* s) { ++pass->counts[topic(s)]; });
  if (taken.empty()) return;
  query("SELECT topic_id, timestamp, data FROM messages WHERE topic_id IN (" + taken + ")",
        [&](sqlite3_stmt* s) {
          const int index = topic(s);
          const auto* data = static_cast<const char*>(sqlite3_column_blob(s, 2));
          const auto bytes = static_cast<std::size_t>(sqlite3_column_bytes(s, 2));
          pass->take(index, sqlite3_column_int64(s, 1),
                     data != nullptr ? std::string_view(data, bytes) : std::string_view());
        });
}

void ReadStorage(const std::string& path, Ros2Pass* pass) {
  if (!path.ends_with(".db3") && !path.ends_with(".mcap"))
    Fail("storage file " + path + " is neither .db3 nor .mcap");
  const std::uint64_t size = RegularFileSize(path);
  if (path.ends_with(".db3")) return ReadSqlite(path, size, pass);
  ReadMcap(path, size, pass);
}

// The storage files a bag directory's metadata.yaml lists: each a regular file inside the
// directory (no absolute path, no "..", no link leading out), listed once, at most
// max_storage_files.
std::vector<std::string> DirectoryFiles(const std::string& dir, const Ros2ReadLimits& limits) {
  const std::string metadata = (std::filesystem::path(dir) / "metadata.yaml").string();
  if (RegularFileSize(metadata) > kMaxMetadataBytes)
    Fail(metadata + ": more than " + std::to_string(kMaxMetadataBytes) + " bytes");
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
  if (files.size() > limits.max_storage_files)
    Fail(metadata + ": " + std::to_string(files.size()) + " relative_file_paths, more than " +
         std::to_string(limits.max_storage_files));
  std::error_code error;
  const std::filesystem::path inside = std::filesystem::canonical(dir, error);
  if (error) Fail(dir + ": " + error.message());
  std::vector<std::string> out;
  std::set<std::filesystem::path> seen;
  for (const YAML::Node& f : files) {
    if (!f.IsScalar()) Fail(metadata + ": relative_file_paths holds a non-string");
    const std::filesystem::path relative(f.Scalar());
    const std::string named = metadata + ": relative_file_paths entry '" + f.Scalar() + "'";
    if (relative.empty() || relative.is_absolute() ||
        std::any_of(relative.begin(), relative.end(),
                    [](const std::filesystem::path& part) { return part == ".."; }))
      Fail(named + " is not a path inside the bag directory");
    const std::filesystem::path real = std::filesystem::canonical(inside / relative, error);
    if (error) Fail(named + ": " + error.message());
    const auto [end, _] = std::mismatch(inside.begin(), inside.end(), real.begin(), real.end());
    if (end != inside.end()) Fail(named + " is a link that leads out of the bag directory");
    if (!seen.insert(real).second) Fail(named + " is listed twice");
    out.push_back((inside / relative).string());
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

Ros2BagFile::Ros2BagFile(const std::string& path, const Ros2ReadLimits& limits) : limits_(limits) {
  if (std::filesystem::is_directory(path)) {
    files_ = DirectoryFiles(path, limits_);
  } else {
    files_ = {path};
  }
  decompression_budget_ = limits_.max_decompressed_bytes;
  for (const std::string& file : files_)
    decompression_budget_ += limits_.decompression_ratio * RegularFileSize(file);
  Ros2Pass pass(limits_);
  pass.decompression_budget = decompression_budget_;
  for (const std::string& file : files_) ReadStorage(file, &pass);
  topics_ = std::move(pass.topics);
  counts_ = std::move(pass.counts);
}

RosBagTopics Ros2BagFile::Topics() const {
  RosBagTopics topics;
  for (std::size_t i = 0; i < topics_.size(); ++i) {
    topics.types[topics_[i].name] = Ros1Name(topics_[i].type);
    int& count = topics.counts[topics_[i].name];
    count = static_cast<int>(std::min<std::int64_t>(count + counts_[i], kMaxCount));
  }
  return topics;
}

RosBagMessages Ros2BagFile::Messages(const std::string& scan_topic, const std::string& odom_topic,
                                     const std::string& truth_topic, bool read_tf) const {
  // Each message decoded as it is read, with its receive time: sorted by it at the end.
  std::vector<std::pair<std::int64_t, RosScan>> scans;
  std::vector<std::pair<std::int64_t, RosPose>> odometry, truth;
  std::vector<std::pair<std::int64_t, std::vector<RosPose>>> tf, tf_static;
  std::uint64_t held = 0;
  Ros2Pass pass(limits_);
  pass.decompression_budget = decompression_budget_;
  pass.wanted = [&](const Ros2Topic& t) {
    return (!scan_topic.empty() && t.name == scan_topic) ||
           (!odom_topic.empty() && t.name == odom_topic) ||
           (!truth_topic.empty() && t.name == truth_topic) || (read_tf && t.name == "/tf") ||
           t.name == "/tf_static";
  };
  pass.take = [&](int index, std::int64_t time_ns, std::string_view data) {
    const Ros2Topic& topic = pass.topics[static_cast<std::size_t>(index)];
    const std::string& name = topic.name;
    held += std::max<std::uint64_t>(data.size(), kHeldBytesPerMessage);
    if (held > limits_.max_held_bytes)
      Fail("the messages of the topics read hold more than " +
           std::to_string(limits_.max_held_bytes) + " bytes, the most a log may hold");
    if (topic.encoding != "cdr")
      Fail("topic " + name + " is serialized as '" + topic.encoding + "'; splam reads cdr");
    const auto fail = [&] {
      Fail("a message on " + name + " does not decode as " + topic.type + " (CDR)");
    };
    if (name == scan_topic) {
      if (topic.type != kLaserScan2 ||
          !DecodeLaserScan(data, &scans.emplace_back(time_ns, RosScan{}).second))
        fail();
    } else if (name == odom_topic || name == truth_topic) {
      RosPose p;
      if (topic.type != kOdometry2 || !DecodeOdometry(data, &p)) fail();
      (name == odom_topic ? odometry : truth).emplace_back(time_ns, std::move(p));
    } else {
      auto& into = name == "/tf" ? tf : tf_static;
      if (topic.type != kTfMessage2 ||
          !DecodeTransforms(data, &into.emplace_back(time_ns, std::vector<RosPose>{}).second))
        fail();
    }
  };
  for (const std::string& file : files_) ReadStorage(file, &pass);
  const auto in_time_order = [](auto* stamped) {
    std::stable_sort(stamped->begin(), stamped->end(),
                     [](const auto& a, const auto& b) { return a.first < b.first; });
  };
  RosBagMessages out;
  const auto move_into = [&](auto* stamped, auto* into) {
    in_time_order(stamped);
    for (auto& [time, message] : *stamped) into->push_back(std::move(message));
  };
  const auto flatten_into = [&](auto* stamped, std::vector<RosPose>* into) {
    in_time_order(stamped);
    for (auto& [time, transforms] : *stamped)
      into->insert(into->end(), std::make_move_iterator(transforms.begin()),
                   std::make_move_iterator(transforms.end()));
  };
  move_into(&scans, &out.scans);
  move_into(&odometry, &out.odometry);
  move_into(&truth, &out.truth);
  flatten_into(&tf, &out.tf);
  flatten_into(&tf_static, &out.tf_static);
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
