#include "base/security_files.hpp"

#include <openssl/bio.h>
#include <openssl/err.h>
#include <openssl/pem.h>
#include <openssl/pkcs7.h>
#include <openssl/x509.h>
#include <openssl/x509_vfy.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <climits>
#include <cstdlib>
#include <memory>
#include <vector>

#include "base/config_error.hpp"

namespace tgw::base {

namespace {

struct Free {
    void operator()(BIO* p) const { BIO_free_all(p); }
    void operator()(X509* p) const { X509_free(p); }
    void operator()(EVP_PKEY* p) const { EVP_PKEY_free(p); }
    void operator()(X509_STORE* p) const { X509_STORE_free(p); }
    void operator()(X509_STORE_CTX* p) const { X509_STORE_CTX_free(p); }
    void operator()(PKCS7* p) const { PKCS7_free(p); }
};
template <typename T>
using Owned = std::unique_ptr<T, Free>;

/// The check of one identity directory: each failure names its file.
class Checker {
  public:
    Checker(std::string dir, std::string flag) : dir_(std::move(dir)), flag_(std::move(flag)) {
        while (dir_.size() > 1 && dir_.back() == '/')
            dir_.pop_back();
    }

    /// `dir`/name as the message shows it.
    std::string shown(const char* name) const { return dir_ + "/" + name; }

    [[noreturn]] void fail(const char* name, const std::string& what) const {
        ERR_clear_error();
        throw ConfigError(flag_ + " " + shown(name) + ": " + what);
    }

    /// The file's absolute path, once it is known to be a readable regular file.
    std::string readable(const char* name) const {
        const std::string path = shown(name);
        struct stat st {};
        if (::stat(path.c_str(), &st) != 0)
            fail(name, "missing (scripts/make-certs makes an identity's six files)");
        if (!S_ISREG(st.st_mode))
            fail(name, "not a regular file");
        if (::access(path.c_str(), R_OK) != 0)
            fail(name, "cannot be read");
        char resolved[PATH_MAX];
        if (::realpath(path.c_str(), resolved) == nullptr)
            fail(name, "cannot be resolved to an absolute path");
        return resolved;
    }

    Owned<BIO> open(const char* name) const {
        Owned<BIO> bio(BIO_new_file(shown(name).c_str(), "r"));
        if (!bio)
            fail(name, "cannot be opened");
        return bio;
    }

    Owned<X509> certificate(const char* name) const {
        Owned<BIO> bio = open(name);
        Owned<X509> cert(PEM_read_bio_X509(bio.get(), nullptr, nullptr, nullptr));
        if (!cert)
            fail(name, "not a PEM certificate" + openssl_reason());
        return cert;
    }

    Owned<EVP_PKEY> private_key(const char* name) const {
        Owned<BIO> bio = open(name);
        Owned<EVP_PKEY> key(PEM_read_bio_PrivateKey(bio.get(), nullptr, nullptr, nullptr));
        if (!key)
            fail(name, "not an unencrypted PEM private key" + openssl_reason());
        return key;
    }

    /// A store that trusts `ca` alone.
    static Owned<X509_STORE> trusting(X509* ca) {
        Owned<X509_STORE> store(X509_STORE_new());
        if (!store || X509_STORE_add_cert(store.get(), ca) != 1)
            throw ConfigError("OpenSSL: cannot make a certificate store");
        return store;
    }

    /// Checks that `cert` chains to `ca` and is valid now.
    void chains_to(const char* cert_name, X509* cert, const char* ca_name, X509* ca) const {
        Owned<X509_STORE> store = trusting(ca);
        Owned<X509_STORE_CTX> ctx(X509_STORE_CTX_new());
        if (!ctx || X509_STORE_CTX_init(ctx.get(), store.get(), cert, nullptr) != 1)
            throw ConfigError("OpenSSL: cannot make a certificate store context");
        if (X509_verify_cert(ctx.get()) != 1) {
            const int error = X509_STORE_CTX_get_error(ctx.get());
            fail(cert_name, std::string("not accepted by ") + shown(ca_name) + " (" +
                                X509_verify_cert_error_string(error) + ")" +
                                (error == X509_V_ERR_UNABLE_TO_GET_ISSUER_CERT_LOCALLY ||
                                         error == X509_V_ERR_DEPTH_ZERO_SELF_SIGNED_CERT ||
                                         error == X509_V_ERR_CERT_SIGNATURE_FAILURE
                                     ? ": a certificate from another CA"
                                     : ""));
        }
    }

    /// The signed text of the S/MIME document `name`, once `ca` verified its signature.
    std::string signed_text(const char* name, const char* ca_name, X509* ca) const {
        Owned<BIO> bio = open(name);
        BIO* content = nullptr;
        Owned<PKCS7> p7(SMIME_read_PKCS7(bio.get(), &content));
        Owned<BIO> owned_content(content);
        if (!p7)
            fail(name, "not an S/MIME (PKCS#7) document" + openssl_reason());
        Owned<X509_STORE> store = trusting(ca);
        Owned<BIO> out(BIO_new(BIO_s_mem()));
        if (PKCS7_verify(p7.get(), nullptr, store.get(), content, out.get(), PKCS7_TEXT) != 1) {
            fail(name, std::string("its signature does not verify with ") + shown(ca_name) +
                           ": tampered with, or signed by another CA" + openssl_reason());
        }
        char* data = nullptr;
        const long size = BIO_get_mem_data(out.get(), &data);
        return size > 0 ? std::string(data, static_cast<std::size_t>(size)) : std::string();
    }

  private:
    /// " (OpenSSL's reason)" for the last error, or nothing.
    static std::string openssl_reason() {
        const unsigned long error = ERR_peek_last_error();
        if (error == 0)
            return {};
        const char* reason = ERR_reason_error_string(error);
        return reason == nullptr ? std::string() : std::string(" (") + reason + ")";
    }

    std::string dir_;
    std::string flag_;
};

/// An RFC 2253 name without blanks around its separators, lower case: how Fast DDS's comparison forgives them.
std::string normalized_name(const std::string& name) {
    std::string out;
    for (std::size_t i = 0; i < name.size(); ++i) {
        const char c = name[i];
        if (std::isspace(static_cast<unsigned char>(c))) {
            const bool after_separator = !out.empty() && (out.back() == ',' || out.back() == '=');
            std::size_t next = i;
            while (next < name.size() && std::isspace(static_cast<unsigned char>(name[next])))
                ++next;
            const bool before_separator = next == name.size() || name[next] == ',' || name[next] == '=';
            if (out.empty() || after_separator || before_separator) {
                i = next - 1;
                continue;
            }
        }
        out.push_back(static_cast<char>(std::tolower(static_cast<unsigned char>(c))));
    }
    return out;
}

std::string subject_rfc2253(X509* cert) {
    Owned<BIO> bio(BIO_new(BIO_s_mem()));
    X509_NAME_print_ex(bio.get(), X509_get_subject_name(cert), 0, XN_FLAG_RFC2253);
    char* data = nullptr;
    const long size = BIO_get_mem_data(bio.get(), &data);
    return size > 0 ? std::string(data, static_cast<std::size_t>(size)) : std::string();
}

/// The text of every <subject_name> element of a permissions document.
std::vector<std::string> subject_names(const std::string& xml) {
    std::vector<std::string> names;
    const std::string open = "<subject_name>";
    const std::string close = "</subject_name>";
    for (std::size_t at = xml.find(open); at != std::string::npos; at = xml.find(open, at)) {
        at += open.size();
        const std::size_t end = xml.find(close, at);
        if (end == std::string::npos)
            break;
        names.push_back(xml.substr(at, end - at));
        at = end;
    }
    return names;
}

}  // namespace

SecurityFiles SecurityFiles::load(const std::string& dir, const std::string& flag) {
    ERR_clear_error();
    struct stat st {};
    if (dir.empty() || ::stat(dir.c_str(), &st) != 0 || !S_ISDIR(st.st_mode))
        throw ConfigError(flag + " " + dir + ": not a directory (an identity made by scripts/make-certs)");
    const Checker check(dir, flag);

    SecurityFiles files;
    // Every file is there before any is read: the message then names the first one missing.
    files.identity_ca = check.readable(IDENTITY_CA);
    files.certificate = check.readable(CERTIFICATE);
    files.private_key = check.readable(PRIVATE_KEY);
    files.permissions_ca = check.readable(PERMISSIONS_CA);
    files.governance = check.readable(GOVERNANCE);
    files.permissions = check.readable(PERMISSIONS);

    const Owned<X509> identity_ca = check.certificate(IDENTITY_CA);
    const Owned<X509> cert = check.certificate(CERTIFICATE);
    check.chains_to(CERTIFICATE, cert.get(), IDENTITY_CA, identity_ca.get());
    const Owned<EVP_PKEY> key = check.private_key(PRIVATE_KEY);
    if (X509_check_private_key(cert.get(), key.get()) != 1)
        check.fail(PRIVATE_KEY, std::string("not the key of ") + check.shown(CERTIFICATE));

    const Owned<X509> permissions_ca = check.certificate(PERMISSIONS_CA);
    const std::string governance = check.signed_text(GOVERNANCE, PERMISSIONS_CA, permissions_ca.get());
    if (governance.find("<domain_access_rules>") == std::string::npos)
        check.fail(GOVERNANCE, "signed, but not a governance document (no <domain_access_rules>)");
    const std::string permissions = check.signed_text(PERMISSIONS, PERMISSIONS_CA, permissions_ca.get());
    const std::string subject = subject_rfc2253(cert.get());
    const std::vector<std::string> granted = subject_names(permissions);
    const bool grants_subject = std::any_of(granted.begin(), granted.end(), [&](const std::string& name) {
        return normalized_name(name) == normalized_name(subject);
    });
    if (!grants_subject) {
        check.fail(PERMISSIONS, "grants nothing to " + check.shown(CERTIFICATE) + "'s subject '" + subject + "'");
    }
    ERR_clear_error();
    return files;
}

}  // namespace tgw::base
