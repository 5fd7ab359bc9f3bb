// The tokens of an IDL file, for IdlParser: comments dropped, preprocessor lines dropped except the targets of
// #include, each token with its line.
#pragma once

#include <string>
#include <vector>

namespace tgw::types {

/// A word, literal or punctuation of IDL text, with its line.
struct IdlToken {
    enum class Kind { identifier, integer, floating, string, character, punctuation, end };

    Kind kind = Kind::end;
    std::string text;  ///< as written; string and character literals without quotes, escapes resolved
    int line = 0;
};

/// An #include line: what it names and where.
struct IdlInclude {
    std::string target;  ///< "std_msgs/msg/Header.idl", as written between the quotes or angle brackets
    int line = 0;
};

/// A file's tokens and its #include lines.
struct IdlTokens {
    std::vector<IdlToken> tokens;  ///< ends with one token of Kind::end
    std::vector<IdlInclude> includes;
};

/// Splits `text` into tokens. "::" is one token; every other punctuation character is a token of its own (so
/// that `sequence<sequence<long>>` closes twice). Throws base::ConfigError "FILE:LINE: ..." naming `file` on an
/// unterminated comment or literal, or a character IDL does not use.
IdlTokens tokenize_idl(const std::string& text, const std::string& file);

}  // namespace tgw::types
