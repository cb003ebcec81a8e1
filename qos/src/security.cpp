// DDS-Security for a participant: the pre-flight check of a security
// directory (OpenSSL) and its mapping to the Fast DDS plugin properties.
//
// Fast DDS refuses a participant whose security files are bad with nothing
// but a nullptr (the reason goes to its log); the check below names the file
// first, for the errors a person can make: a missing file, an identity from
// another CA or out of date, a document signed by another CA or edited.
#include <openssl/err.h>
#include <openssl/pem.h>
#include <openssl/pkcs7.h>
#include <openssl/x509.h>
#include <openssl/x509_vfy.h>
#include <sys/stat.h>

#include <cstdio>
#include <memory>

#include "mtc/qos/participant.hpp"
#include "mtc/qos/participant_qos.hpp"

namespace mtc::qos {

namespace {

template <typename T, void (*Free)(T*)>
struct Deleter {
  void operator()(T* p) const noexcept { Free(p); }
};
using Bio = std::unique_ptr<BIO, Deleter<BIO, BIO_free_all>>;
using Cert = std::unique_ptr<X509, Deleter<X509, X509_free>>;
using Key = std::unique_ptr<EVP_PKEY, Deleter<EVP_PKEY, EVP_PKEY_free>>;
using Store = std::unique_ptr<X509_STORE, Deleter<X509_STORE, X509_STORE_free>>;
using StoreContext = std::unique_ptr<X509_STORE_CTX, Deleter<X509_STORE_CTX, X509_STORE_CTX_free>>;
using Pkcs7 = std::unique_ptr<PKCS7, Deleter<PKCS7, PKCS7_free>>;

// OpenSSL's first queued error in words (and the queue emptied).
std::string openssl_error() {
  const unsigned long code = ERR_get_error();
  ERR_clear_error();
  if (code == 0) return "unknown OpenSSL error";
  char text[256];
  ERR_error_string_n(code, text, sizeof text);
  return text;
}

Bio open_file(const std::string& path) {
  return Bio(BIO_new_file(path.c_str(), "rb"));
}

Cert read_certificate(const std::string& path) {
  Bio bio = open_file(path);
  return Cert(bio ? PEM_read_bio_X509(bio.get(), nullptr, nullptr, nullptr) : nullptr);
}

// Verifies `cert` against the one trusted certificate `ca`, validity dates
// included; returns the verification error in words or nullopt.
std::optional<std::string> verify_certificate(X509* cert, X509* ca) {
  Store store(X509_STORE_new());
  StoreContext context(X509_STORE_CTX_new());
  if (!store || !context || X509_STORE_add_cert(store.get(), ca) != 1 ||
      X509_STORE_CTX_init(context.get(), store.get(), cert, nullptr) != 1) {
    return openssl_error();
  }
  if (X509_verify_cert(context.get()) == 1) return std::nullopt;
  return X509_verify_cert_error_string(X509_STORE_CTX_get_error(context.get()));
}

// An S/MIME document (governance, permissions) must verify against ca.
std::optional<std::string> verify_signed_document(const std::string& path, X509* ca) {
  Bio bio = open_file(path);
  BIO* content = nullptr;
  Pkcs7 p7(bio ? SMIME_read_PKCS7(bio.get(), &content) : nullptr);
  Bio content_owner(content);
  if (!p7) return "not an S/MIME signed document (" + openssl_error() + ")";
  Store store(X509_STORE_new());
  if (!store || X509_STORE_add_cert(store.get(), ca) != 1) return openssl_error();
  Bio sink(BIO_new(BIO_s_mem()));
  if (PKCS7_verify(p7.get(), nullptr, store.get(), content, sink.get(), 0) != 1) {
    return "signature does not verify against ca.pem: edited, or signed by another CA (" +
           openssl_error() + ")";
  }
  return std::nullopt;
}

std::optional<std::string> check_identity(const std::string& dir, X509* ca) {
  const std::string cert_path = dir + "/cert.pem";
  Cert cert = read_certificate(cert_path);
  if (!cert) return cert_path + ": not a PEM certificate";
  if (auto problem = verify_certificate(cert.get(), ca)) {
    return cert_path + ": identity certificate rejected: " + *problem;
  }
  const std::string key_path = dir + "/key.pem";
  Bio bio = open_file(key_path);
  Key key(bio ? PEM_read_bio_PrivateKey(bio.get(), nullptr, nullptr, nullptr) : nullptr);
  if (!key) return key_path + ": not a PEM private key (" + openssl_error() + ")";
  if (X509_check_private_key(cert.get(), key.get()) != 1) {
    ERR_clear_error();
    return key_path + ": not the key of " + cert_path;
  }
  return std::nullopt;
}

}  // namespace

std::optional<std::string> check_security_dir(const std::string& dir) {
  struct stat info {};
  if (::stat(dir.c_str(), &info) != 0 || !S_ISDIR(info.st_mode)) {
    return "security directory " + dir + " does not exist";
  }
  for (const char* file : kSecurityFiles) {
    const std::string path = dir + "/" + file;
    if (std::FILE* f = std::fopen(path.c_str(), "rb")) {
      std::fclose(f);
    } else {
      return path + ": missing or unreadable (scripts/security/make-pki.sh makes it)";
    }
  }
  const std::string ca_path = dir + "/ca.pem";
  Cert ca = read_certificate(ca_path);
  if (!ca) return ca_path + ": not a PEM certificate";
  if (auto problem = check_identity(dir, ca.get())) return problem;
  for (const char* file : {"governance.p7s", "permissions.p7s"}) {
    const std::string path = dir + "/" + file;
    if (auto problem = verify_signed_document(path, ca.get())) return path + ": " + *problem;
  }
  return std::nullopt;
}

std::vector<std::pair<std::string, std::string>> security_properties(const std::string& dir) {
  const std::string uri = "file://" + dir + "/";
  return {
      {"dds.sec.auth.plugin", "builtin.PKI-DH"},
      {"dds.sec.auth.builtin.PKI-DH.identity_ca", uri + "ca.pem"},
      {"dds.sec.auth.builtin.PKI-DH.identity_certificate", uri + "cert.pem"},
      {"dds.sec.auth.builtin.PKI-DH.private_key", uri + "key.pem"},
      {"dds.sec.access.plugin", "builtin.Access-Permissions"},
      {"dds.sec.access.builtin.Access-Permissions.permissions_ca", uri + "ca.pem"},
      {"dds.sec.access.builtin.Access-Permissions.governance", uri + "governance.p7s"},
      {"dds.sec.access.builtin.Access-Permissions.permissions", uri + "permissions.p7s"},
      {"dds.sec.crypto.plugin", "builtin.AES-GCM-GMAC"},
  };
}

}  // namespace mtc::qos
