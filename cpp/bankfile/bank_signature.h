// Optional Ed25519 signatures of bank files (libsodium's crypto_sign_*, RFC 8032).
//
// The bank hash detects corruption, not substitution: anyone can write a well-formed bank with
// a correct SHA-256. A signature says who made it. It is detached, in FILE.sig beside the bank
// (64 bytes), and covers the bank file's bytes exactly (header, so the content hash, and
// payload). Keys are raw files: the public key 32 bytes, the secret key 64 bytes (libsodium's
// layout: seed then public key), written with mode 0600.
//
// load_signed_bank reads the bank once (read_regular_file, bank_file.h), verifies the
// signature over those bytes with the public key, and only then parses and validates them;
// so what is verified is what is loaded. It throws BankSignatureError (a BankFileFormatError,
// std::invalid_argument) when the .sig is missing, is not 64 bytes, or does not verify, and
// when the key file is not 32 bytes; the file errors of read_regular_file otherwise.
#pragma once

#include <string>

#include "bankfile/bank_file.h"

namespace f16mmae {

inline constexpr std::size_t kBankPublicKeyBytes = 32;
inline constexpr std::size_t kBankSecretKeyBytes = 64;
inline constexpr std::size_t kBankSignatureBytes = 64;

class BankSignatureError : public BankFileFormatError {
  using BankFileFormatError::BankFileFormatError;
};

// Path of the detached signature of a bank file: bank_path + ".sig".
std::string bank_signature_path(const std::string& bank_path);
// Writes a new key pair (public_key_path 0644, secret_key_path 0600). Throws BankFileIoError.
void generate_bank_signing_keys(const std::string& public_key_path, const std::string& secret_key_path);
// Signs the bank file's bytes with the secret key, writing bank_signature_path(bank_path).
void sign_bank_file(const std::string& bank_path, const std::string& secret_key_path);
// Verifies the bank's signature with the public key, then parses and validates it.
ModelBank load_signed_bank(const std::string& bank_path, const std::string& public_key_path);

}  // namespace f16mmae
