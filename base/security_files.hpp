// The files of one DDS Security identity (scripts/make-certs), checked before any participant uses them: Fast DDS
// itself only logs a vague line and then fails to create the participant, or creates one that matches no one.
#pragma once

#include <string>

namespace tgw::base {

/// One identity's six files, by path. Made by load(), whose checks they passed.
struct SecurityFiles {
    static constexpr const char* IDENTITY_CA = "identity_ca.pem";
    static constexpr const char* CERTIFICATE = "cert.pem";
    static constexpr const char* PRIVATE_KEY = "key.pem";
    static constexpr const char* PERMISSIONS_CA = "permissions_ca.pem";
    static constexpr const char* GOVERNANCE = "governance.p7s";
    static constexpr const char* PERMISSIONS = "permissions.p7s";

    std::string identity_ca;
    std::string certificate;
    std::string private_key;
    std::string permissions_ca;
    std::string governance;
    std::string permissions;

    /// The files of the identity directory `dir`, as absolute paths, after checking with OpenSSL that each is
    /// there and readable, that cert.pem chains to identity_ca.pem and is valid now, that key.pem is cert.pem's
    /// key, that governance.p7s and permissions.p7s are S/MIME documents whose signature permissions_ca.pem
    /// verifies (neither tampered with nor signed by another CA), and that permissions.p7s grants something to
    /// cert.pem's subject. Throws ConfigError "`flag` FILE: what is wrong", FILE as `dir`/name.
    static SecurityFiles load(const std::string& dir, const std::string& flag);
};

}  // namespace tgw::base
