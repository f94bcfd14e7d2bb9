// PayloadReader — reads the LCM encoding of a model bank (lcm_types/lcmt_model_bank.lcm) from
// untrusted bytes, field by field, in the order of the .lcm file.
//
// LCM encoding (big-endian): int32/int64/double as 4/8/8 bytes; a string as int32 n (its
// length + 1), n - 1 bytes, a NUL; an array as its elements, its length being an earlier
// int32 field; a matrix (lcmt_bank_matrix) as int32 rows, int32 cols, rows * cols doubles.
//
// Every declared count is checked BEFORE anything is allocated, in 64-bit arithmetic:
//   0 <= count <= the model's limit (bank_file.h: kMaxBank*), and
//   count * (smallest encoded element) <= the bytes that remain.
// So no declared size can overflow, allocate more than the payload could hold, or read past
// the end. A refusal is a BankFileFormatError naming the field and the value:
//   "payload field hypotheses[3].phi: rows = 268435456 exceeds the limit of 256".
#pragma once

#include <Eigen/Dense>

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "bankfile/bank_file.h"

namespace f16mmae {

class PayloadReader {
 public:
  PayloadReader(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}

  std::int32_t i32(const std::string& field) { return static_cast<std::int32_t>(be(field, 4)); }
  std::int64_t i64(const std::string& field) { return static_cast<std::int64_t>(be(field, 8)); }
  double f64(const std::string& field) {
    const std::uint64_t bits = be(field, 8);
    double v;
    std::memcpy(&v, &bits, sizeof v);
    return v;
  }

  // An int32 count in [0, limit] whose elements, each at least min_element_bytes, fit.
  std::size_t count(const std::string& field, std::int64_t limit, std::int64_t min_element_bytes) {
    const std::size_t at = pos_;
    const std::int64_t n = i32(field);
    if (n < 0 || n > limit)
      fail(field, at, "= " + std::to_string(n) + (n < 0 ? " is negative" : " exceeds the limit of " + std::to_string(limit)));
    if (n * min_element_bytes > static_cast<std::int64_t>(remaining()))
      fail(field, at, "= " + std::to_string(n) + " needs at least " + std::to_string(n * min_element_bytes) +
                          " bytes, " + std::to_string(remaining()) + " remain");
    return static_cast<std::size_t>(n);
  }

  // A string of at most max_bytes bytes (plus its NUL).
  std::string text(const std::string& field, std::int64_t max_bytes) {
    const std::size_t at = pos_;
    const std::size_t n = count(field + " length", max_bytes + 1, 1);
    if (n == 0) fail(field, at, "has length 0 (an LCM string holds at least its NUL)");
    if (data_[pos_ + n - 1] != 0) fail(field, at, "is not NUL-terminated");
    std::string out(reinterpret_cast<const char*>(data_ + pos_), n - 1);
    pos_ += n;
    return out;
  }

  // int32 count_field, then that many strings (at most kMaxBankDimension, each a name).
  std::vector<std::string> names(const std::string& field, const std::string& count_field) {
    const std::size_t n = count(count_field, kMaxBankDimension, 5);
    std::vector<std::string> out(n);
    for (std::size_t i = 0; i < n; ++i) out[i] = text(field + "[" + std::to_string(i) + "]", kMaxBankNameBytes);
    return out;
  }

  // int32 size_field, then that many doubles.
  Eigen::VectorXd vector(const std::string& field, const std::string& size_field) {
    const std::size_t n = count(size_field, kMaxBankDimension, 8);
    Eigen::VectorXd out(static_cast<Eigen::Index>(n));
    for (std::size_t i = 0; i < n; ++i) out(static_cast<Eigen::Index>(i)) = f64(field);
    return out;
  }

  // n doubles whose count was declared earlier (an array sharing another array's size field).
  Eigen::VectorXd doubles(const std::string& field, Eigen::Index n) {
    if (static_cast<std::uint64_t>(n) * 8 > remaining())
      fail(field, pos_, "needs " + std::to_string(n * 8) + " bytes, but " + std::to_string(remaining()) + " remain");
    Eigen::VectorXd out(n);
    for (Eigen::Index i = 0; i < n; ++i) out(i) = f64(field);
    return out;
  }

  // An lcmt_bank_matrix: rows, cols (each at most kMaxBankDimension), row-major data.
  Eigen::MatrixXd matrix(const std::string& field) {
    const std::size_t rows = count(field + ".rows", kMaxBankDimension, 0);
    const std::size_t cols = count(field + ".cols", kMaxBankDimension, 0);
    const std::size_t at = pos_;
    const std::uint64_t bytes = static_cast<std::uint64_t>(rows) * cols * 8;  // <= 256 * 256 * 8
    if (bytes > remaining())
      fail(field, at, "is " + std::to_string(rows) + "x" + std::to_string(cols) + ", " + std::to_string(bytes) +
                          " bytes, but " + std::to_string(remaining()) + " remain");
    Eigen::MatrixXd out(static_cast<Eigen::Index>(rows), static_cast<Eigen::Index>(cols));
    for (std::size_t i = 0; i < rows; ++i)
      for (std::size_t j = 0; j < cols; ++j) out(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = f64(field);
    return out;
  }

  // n raw bytes, n checked against the bytes left first; returns where they start.
  const std::uint8_t* bytes(const std::string& field, std::uint64_t n) {
    if (n > remaining())
      fail(field, pos_, "declares " + std::to_string(n) + " bytes, " + std::to_string(remaining()) + " remain");
    const std::uint8_t* at = data_ + pos_;
    pos_ += static_cast<std::size_t>(n);
    return at;
  }

  // The message must end exactly at the end of the payload.
  void finish() const {
    if (pos_ != size_)
      throw BankFileFormatError("payload has " + std::to_string(size_ - pos_) +
                                " bytes after the f16mmae.lcmt_model_bank message");
  }

  std::size_t remaining() const { return size_ - pos_; }

 private:
  std::uint64_t be(const std::string& field, int bytes) {
    if (remaining() < static_cast<std::size_t>(bytes))
      fail(field, pos_, "is cut off: " + std::to_string(bytes) + " bytes needed, " + std::to_string(remaining()) +
                            " remain");
    std::uint64_t v = 0;
    for (int i = 0; i < bytes; ++i) v = (v << 8) | data_[pos_ + i];
    pos_ += static_cast<std::size_t>(bytes);
    return v;
  }

  [[noreturn]] static void fail(const std::string& field, std::size_t at, const std::string& what) {
    throw BankFileFormatError("payload field " + field + " (byte " + std::to_string(at) + ") " + what);
  }

  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t pos_ = 0;
};

}  // namespace f16mmae
