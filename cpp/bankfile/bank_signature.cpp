// Ed25519 signatures of bank files; see bank_signature.h.
#include "bankfile/bank_signature.h"

#include <fcntl.h>
#include <sodium.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <vector>

namespace f16mmae {
namespace {

void init_sodium() {
  if (sodium_init() < 0) throw BankFileIoError("libsodium cannot initialise (no entropy source?)");
}

// A key or signature file of exactly `size` bytes.
std::vector<std::uint8_t> read_exact(const std::string& path, std::size_t size, const std::string& what) {
  std::vector<std::uint8_t> bytes = read_regular_file(path, size, what);
  if (bytes.size() != size)
    throw BankSignatureError(what + " '" + path + "': is " + std::to_string(bytes.size()) + " bytes, expected " +
                             std::to_string(size));
  return bytes;
}

void write_file(const std::string& path, const std::uint8_t* data, std::size_t size, mode_t mode) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, mode);
  if (fd < 0) throw BankFileIoError("'" + path + "': cannot create it (" + std::strerror(errno) + ")");
  std::size_t done = 0;
  while (done < size) {
    const ssize_t n = ::write(fd, data + done, size - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const std::string e = std::strerror(errno);
      ::close(fd);
      throw BankFileIoError("'" + path + "': write failed (" + e + ")");
    }
    done += static_cast<std::size_t>(n);
  }
  if (::fchmod(fd, mode) != 0 || ::close(fd) != 0)
    throw BankFileIoError("'" + path + "': cannot finish it (" + std::strerror(errno) + ")");
}

}  // namespace

std::string bank_signature_path(const std::string& bank_path) { return bank_path + ".sig"; }

void generate_bank_signing_keys(const std::string& public_key_path, const std::string& secret_key_path) {
  init_sodium();
  std::uint8_t pk[crypto_sign_PUBLICKEYBYTES], sk[crypto_sign_SECRETKEYBYTES];
  static_assert(sizeof pk == kBankPublicKeyBytes && sizeof sk == kBankSecretKeyBytes);
  crypto_sign_keypair(pk, sk);
  write_file(secret_key_path, sk, sizeof sk, 0600);
  sodium_memzero(sk, sizeof sk);
  write_file(public_key_path, pk, sizeof pk, 0644);
}

void sign_bank_file(const std::string& bank_path, const std::string& secret_key_path) {
  init_sodium();
  const std::vector<std::uint8_t> bank = read_bank_bytes(bank_path);
  std::vector<std::uint8_t> sk = read_exact(secret_key_path, kBankSecretKeyBytes, "secret key");
  std::uint8_t sig[crypto_sign_BYTES];
  static_assert(sizeof sig == kBankSignatureBytes);
  crypto_sign_detached(sig, nullptr, bank.data(), bank.size(), sk.data());
  sodium_memzero(sk.data(), sk.size());
  write_file(bank_signature_path(bank_path), sig, sizeof sig, 0644);
}

ModelBank load_signed_bank(const std::string& bank_path, const std::string& public_key_path) {
  init_sodium();
  const std::vector<std::uint8_t> bank = read_bank_bytes(bank_path);
  const std::vector<std::uint8_t> pk = read_exact(public_key_path, kBankPublicKeyBytes, "public key");
  const std::string sig_path = bank_signature_path(bank_path);
  std::vector<std::uint8_t> sig;
  try {
    sig = read_exact(sig_path, kBankSignatureBytes, "bank signature");
  } catch (const BankFileNotFound&) {
    throw BankSignatureError("bank file '" + bank_path + "': no signature '" + sig_path +
                             "', and a public key was given: the bank must be signed");
  }
  if (crypto_sign_verify_detached(sig.data(), bank.data(), bank.size(), pk.data()) != 0)
    throw BankSignatureError("bank file '" + bank_path + "': its signature '" + sig_path +
                             "' does not verify with the public key '" + public_key_path +
                             "': the file was changed after signing, or another key signed it");
  return parse_any_bank_file(bank.data(), bank.size(), "'" + bank_path + "'");
}

}  // namespace f16mmae
