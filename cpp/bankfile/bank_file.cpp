// Bank file header, checks and atomic I/O; see bank_file.h for the layout.
#include "bankfile/bank_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

#include "bankfile/schedule_file.h"
#include "bankfile/sha256.h"

namespace f16mmae {
namespace {

constexpr std::size_t kVersionOffset = 8, kSizeOffset = 12, kHashOffset = 20;

void put_be(std::uint8_t* out, std::uint64_t value, int bytes) {
  for (int i = 0; i < bytes; ++i) out[i] = static_cast<std::uint8_t>(value >> (8 * (bytes - 1 - i)));
}

std::uint64_t get_be(const std::uint8_t* in, int bytes) {
  std::uint64_t value = 0;
  for (int i = 0; i < bytes; ++i) value = (value << 8) | in[i];
  return value;
}

std::string printable(const std::uint8_t* p, std::size_t n) {
  std::string out;
  for (std::size_t i = 0; i < n; ++i) {
    if (p[i] >= 0x20 && p[i] < 0x7f) {
      out += static_cast<char>(p[i]);
    } else {
      static const char* kHex = "0123456789abcdef";
      out += "\\x";
      out += kHex[p[i] >> 4];
      out += kHex[p[i] & 0xf];
    }
  }
  return out;
}

std::string errno_text() { return std::strerror(errno); }

// Writes all of `bytes` to fd, retrying short writes.
bool write_all(int fd, const std::uint8_t* bytes, std::size_t size) {
  while (size > 0) {
    const ssize_t n = ::write(fd, bytes, size);
    if (n < 0) {
      if (errno == EINTR) continue;
      return false;
    }
    bytes += n;
    size -= static_cast<std::size_t>(n);
  }
  return true;
}

}  // namespace

std::vector<std::uint8_t> hashed_file_image(const char (&magic)[8], std::uint32_t version,
                                            const std::vector<std::uint8_t>& payload) {
  const Sha256Digest digest = sha256(payload.data(), payload.size());
  std::vector<std::uint8_t> image(kBankFileHeaderSize + payload.size());
  std::memcpy(image.data(), magic, sizeof magic);
  put_be(image.data() + kVersionOffset, version, 4);
  put_be(image.data() + kSizeOffset, payload.size(), 8);
  std::memcpy(image.data() + kHashOffset, digest.data(), digest.size());
  std::memcpy(image.data() + kBankFileHeaderSize, payload.data(), payload.size());
  return image;
}

std::uint32_t hashed_file_version(const std::uint8_t* data, std::size_t size, const char (&magic)[8],
                                  const std::string& who, const std::string& kind) {
  auto fail = [&](const std::string& what) { throw BankFileFormatError(who + what); };
  if (size == 0) fail("truncated: the file is empty");
  if (std::memcmp(data, magic, std::min(size, sizeof magic)) != 0)
    fail("wrong magic bytes '" + printable(data, std::min(size, sizeof magic)) + "' (expected '" +
         std::string(magic, sizeof magic) + "'): not a " + kind + " file");
  if (size < kBankFileHeaderSize)
    fail("truncated: " + std::to_string(size) + " bytes, the header alone has " +
         std::to_string(kBankFileHeaderSize));
  return static_cast<std::uint32_t>(get_be(data + kVersionOffset, 4));
}

const std::uint8_t* hashed_file_payload(const std::uint8_t* data, std::size_t size, const std::string& who) {
  auto fail = [&](const std::string& what) { throw BankFileFormatError(who + what); };
  const std::uint64_t declared = get_be(data + kSizeOffset, 8);
  const std::size_t present = size - kBankFileHeaderSize;
  if (present < declared)
    fail("truncated: the payload has " + std::to_string(present) + " bytes, the header declares " +
         std::to_string(declared));
  if (present > declared)
    fail(std::to_string(present - declared) + " unexpected bytes after the " + std::to_string(declared) +
         "-byte payload");
  const std::uint8_t* payload = data + kBankFileHeaderSize;
  Sha256Digest stored;
  std::memcpy(stored.data(), data + kHashOffset, stored.size());
  const Sha256Digest actual = sha256(payload, present);
  if (actual != stored)
    fail("content hash mismatch, the file is corrupted: the header records " + to_hex(stored) +
         ", the payload hashes to " + to_hex(actual));
  return payload;
}

std::vector<std::uint8_t> bank_file_bytes(const ModelBank& bank) {
  bank.validate();
  return hashed_file_image(kBankFileMagic, ModelBank::kFormatVersion, encode_bank_payload(bank));
}

ModelBank parse_bank_file(const std::uint8_t* data, std::size_t size, const std::string& source) {
  const std::string who = "bank file " + source + ": ";
  auto fail = [&](const std::string& what) { throw BankFileFormatError(who + what); };
  const std::uint32_t version = hashed_file_version(data, size, kBankFileMagic, who, "model-bank");
  if (version >= 1 && version <= 3)
    fail("format version " + std::to_string(version) + " is no longer read: this build reads version " +
         std::to_string(ModelBank::kFormatVersion) +
         ", where the estimator settings are typed fields and each hypothesis carries the widths of its "
         "uninformative channels and its recommended evidence dwell (dwell_nats). Regenerate the bank with the design command "
         "recorded in its metadata, e.g. `f16mmae design --mach 0.4 --alt-ft 20000 --tuning tuned --out FILE` "
         "(the shipped banks: `python -m f16mmae.design.calibrate --banks`)");
  if (version != ModelBank::kFormatVersion)
    fail("unsupported format version " + std::to_string(version) + " (this build reads version " +
         std::to_string(ModelBank::kFormatVersion) + ")");
  const std::uint8_t* payload = hashed_file_payload(data, size, who);
  const std::size_t present = size - kBankFileHeaderSize;
  ModelBank bank;
  try {
    bank = decode_bank_payload(payload, present);
    bank.validate();
  } catch (const BankFileFormatError& e) {
    fail(e.what());
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(who + e.what());
  }
  return bank;
}

std::string save_bank(const ModelBank& bank, const std::string& path) {
  const std::vector<std::uint8_t> image = bank_file_bytes(bank);  // validates first
  write_file_atomically(image, path, "bank file");
  return to_hex(sha256(image.data() + kBankFileHeaderSize, image.size() - kBankFileHeaderSize));
}

void write_file_atomically(const std::vector<std::uint8_t>& image, const std::string& path, const std::string& what) {
  const std::string who = what + " '" + path + "': ";
  std::string temp = path + ".tmp-XXXXXX";
  const int fd = ::mkstemp(temp.data());
  if (fd < 0) throw BankFileIoError(who + "cannot create a temporary file beside it (" + errno_text() + ")");
  const bool written = write_all(fd, image.data(), image.size()) && ::fchmod(fd, 0644) == 0 && ::fsync(fd) == 0;
  const std::string write_error = errno_text();
  const bool closed = ::close(fd) == 0;
  if (!written || !closed) {
    ::unlink(temp.c_str());
    throw BankFileIoError(who + "write failed (" + (written ? errno_text() : write_error) + ")");
  }
  if (::rename(temp.c_str(), path.c_str()) != 0) {
    const std::string e = errno_text();
    ::unlink(temp.c_str());
    throw BankFileIoError(who + "cannot replace it (" + e + ")");
  }
}

std::vector<std::uint8_t> read_regular_file(const std::string& path, std::uint64_t max_bytes,
                                            const std::string& what) {
  const std::string who = what + " '" + path + "': ";
  // O_NONBLOCK: opening a FIFO with no writer returns at once instead of waiting for one.
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
  if (fd < 0) {
    if (errno == ENOENT) throw BankFileNotFound(who + "no such file");
    throw BankFileIoError(who + "cannot open it (" + errno_text() + ")");
  }
  struct FdCloser {
    int fd;
    ~FdCloser() { ::close(fd); }
  } closer{fd};
  struct stat st {};
  if (::fstat(fd, &st) != 0) throw BankFileIoError(who + "cannot stat it (" + errno_text() + ")");
  if (!S_ISREG(st.st_mode)) {
    const char* kind = S_ISDIR(st.st_mode)    ? "a directory"
                       : S_ISFIFO(st.st_mode) ? "a FIFO"
                       : S_ISCHR(st.st_mode)  ? "a character device"
                       : S_ISBLK(st.st_mode)  ? "a block device"
                       : S_ISSOCK(st.st_mode) ? "a socket"
                                              : "not a regular file";
    throw BankFileIoError(who + "is " + kind + "; it must be a regular file");
  }
  const std::uint64_t size = static_cast<std::uint64_t>(st.st_size);
  if (size > max_bytes)
    throw BankFileFormatError(who + "is " + std::to_string(size) + " bytes, over the limit of " +
                              std::to_string(max_bytes) + " bytes");
  // One byte more than the size: a file that grows while being read is noticed, not cut.
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(size) + 1);
  std::size_t got = 0;
  while (got < bytes.size()) {
    const ssize_t n = ::read(fd, bytes.data() + got, bytes.size() - got);
    if (n < 0) {
      if (errno == EINTR) continue;
      throw BankFileIoError(who + "read failed (" + errno_text() + ")");
    }
    if (n == 0) break;
    got += static_cast<std::size_t>(n);
  }
  if (got != size) throw BankFileIoError(who + "changed size while being read");
  bytes.resize(static_cast<std::size_t>(size));
  return bytes;
}

std::vector<std::uint8_t> read_bank_bytes(const std::string& path) {
  try {
    return read_regular_file(path, kMaxBankFileBytes, "bank file");
  } catch (const BankFileFormatError&) {  // over a bank's limit: a scheduled bank may be larger
    std::vector<std::uint8_t> bytes = read_regular_file(path, kMaxScheduleFileBytes, "bank file");
    if (!is_schedule_file(bytes.data(), bytes.size())) throw;
    return bytes;
  }
}

ModelBank parse_any_bank_file(const std::uint8_t* data, std::size_t size, const std::string& source) {
  if (is_schedule_file(data, size)) return parse_schedule_file(data, size, source);
  return parse_bank_file(data, size, source);
}

ModelBank load_bank(const std::string& path) {
  const std::vector<std::uint8_t> bytes = read_bank_bytes(path);
  return parse_any_bank_file(bytes.data(), bytes.size(), "'" + path + "'");
}

}  // namespace f16mmae
