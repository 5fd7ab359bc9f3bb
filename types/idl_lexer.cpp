#include "types/idl_lexer.hpp"

#include <cctype>
#include <cstring>

#include "base/config_error.hpp"

namespace tgw::types {

namespace {

constexpr const char* PUNCTUATION = "{}()[]<>;,:=@+-*/%|&^~";

bool is_identifier_start(char c) {
    return std::isalpha(static_cast<unsigned char>(c)) != 0 || c == '_';
}

bool is_identifier_char(char c) {
    return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_';
}

bool is_digit(char c) {
    return std::isdigit(static_cast<unsigned char>(c)) != 0;
}

class Lexer {
  public:
    Lexer(const std::string& text, const std::string& file) : text_(text), file_(file) {}

    IdlTokens run() {
        bool line_start = true;
        while (pos_ < text_.size()) {
            const char c = text_[pos_];
            if (c == '\n') {
                ++line_;
                ++pos_;
                line_start = true;
            } else if (std::isspace(static_cast<unsigned char>(c)) != 0) {
                ++pos_;
            } else if (c == '#' && line_start) {
                directive();
            } else if (starts_with("//")) {
                while (pos_ < text_.size() && text_[pos_] != '\n')
                    ++pos_;
            } else if (starts_with("/*")) {
                block_comment();
            } else {
                line_start = false;
                token();
            }
        }
        out_.tokens.push_back({IdlToken::Kind::end, "", line_});
        return std::move(out_);
    }

  private:
    [[noreturn]] void fail(const std::string& what, int line) const {
        throw base::ConfigError(file_ + ":" + std::to_string(line) + ": " + what);
    }

    bool starts_with(const char* prefix) const { return text_.compare(pos_, std::strlen(prefix), prefix) == 0; }

    char peek(std::size_t ahead = 0) const { return pos_ + ahead < text_.size() ? text_[pos_ + ahead] : '\0'; }

    void block_comment() {
        const int first = line_;
        pos_ += 2;
        while (pos_ < text_.size() && !starts_with("*/")) {
            if (text_[pos_] == '\n')
                ++line_;
            ++pos_;
        }
        if (pos_ >= text_.size())
            fail("a comment that never ends (/* without */)", first);
        pos_ += 2;
    }

    /// A preprocessor line: #include targets are kept, everything else (#pragma, include guards) is dropped.
    void directive() {
        const int line = line_;
        std::string body;
        while (pos_ < text_.size() && text_[pos_] != '\n') {
            if (text_[pos_] == '\\' && peek(1) == '\n') {
                ++line_;
                pos_ += 2;
                continue;
            }
            body += text_[pos_++];
        }
        std::size_t at = body.find_first_not_of(" \t", 1);
        if (at == std::string::npos || body.compare(at, 7, "include") != 0)
            return;
        at = body.find_first_not_of(" \t", at + 7);
        if (at == std::string::npos || (body[at] != '"' && body[at] != '<'))
            fail("#include needs \"FILE\" or <FILE>", line);
        const char close = body[at] == '"' ? '"' : '>';
        const std::size_t end = body.find(close, at + 1);
        if (end == std::string::npos)
            fail("#include: the file name is not closed", line);
        out_.includes.push_back({body.substr(at + 1, end - at - 1), line});
    }

    void token() {
        const char c = text_[pos_];
        if (is_identifier_start(c)) {
            const std::size_t start = pos_;
            while (pos_ < text_.size() && is_identifier_char(text_[pos_]))
                ++pos_;
            push(IdlToken::Kind::identifier, text_.substr(start, pos_ - start));
        } else if (is_digit(c) || (c == '.' && is_digit(peek(1)))) {
            number();
        } else if (c == '"') {
            push(IdlToken::Kind::string, quoted('"'));
        } else if (c == '\'') {
            push(IdlToken::Kind::character, quoted('\''));
        } else if (starts_with("::")) {
            pos_ += 2;
            push(IdlToken::Kind::punctuation, "::");
        } else if (std::strchr(PUNCTUATION, c) != nullptr) {
            ++pos_;
            push(IdlToken::Kind::punctuation, std::string(1, c));
        } else {
            fail(std::string("unexpected character '") + c + "'", line_);
        }
    }

    void number() {
        const std::size_t start = pos_;
        bool floating = false;
        if (peek() == '0' && (peek(1) == 'x' || peek(1) == 'X')) {
            pos_ += 2;
            while (std::isxdigit(static_cast<unsigned char>(peek())) != 0)
                ++pos_;
        } else {
            while (is_digit(peek()))
                ++pos_;
            if (peek() == '.') {
                floating = true;
                ++pos_;
                while (is_digit(peek()))
                    ++pos_;
            }
            if (peek() == 'e' || peek() == 'E') {
                floating = true;
                ++pos_;
                if (peek() == '+' || peek() == '-')
                    ++pos_;
                while (is_digit(peek()))
                    ++pos_;
            }
        }
        const std::string text = text_.substr(start, pos_ - start);
        // Suffixes: d/D of fixed-point constants, and C's habits.
        while (std::strchr("dDlLuUfF", peek()) != nullptr && peek() != '\0')
            ++pos_;
        if (is_identifier_char(peek()))
            fail("'" + text + peek() + "' is not a number", line_);
        push(floating ? IdlToken::Kind::floating : IdlToken::Kind::integer, text);
    }

    std::string quoted(char quote) {
        const int first = line_;
        std::string value;
        ++pos_;
        while (pos_ < text_.size() && text_[pos_] != quote) {
            char c = text_[pos_++];
            if (c == '\n')
                fail("a literal that never ends (missing " + std::string(1, quote) + ")", first);
            if (c == '\\' && pos_ < text_.size()) {
                const char e = text_[pos_++];
                switch (e) {
                    case 'n':
                        c = '\n';
                        break;
                    case 't':
                        c = '\t';
                        break;
                    case 'r':
                        c = '\r';
                        break;
                    case '0':
                        c = '\0';
                        break;
                    default:
                        c = e;  // \\, \", \' and the rest as themselves
                }
            }
            value += c;
        }
        if (pos_ >= text_.size())
            fail("a literal that never ends (missing " + std::string(1, quote) + ")", first);
        ++pos_;
        return value;
    }

    void push(IdlToken::Kind kind, std::string text) { out_.tokens.push_back({kind, std::move(text), line_}); }

    const std::string& text_;
    const std::string& file_;
    std::size_t pos_ = 0;
    int line_ = 1;
    IdlTokens out_;
};

}  // namespace

IdlTokens tokenize_idl(const std::string& text, const std::string& file) {
    return Lexer(text, file).run();
}

}  // namespace tgw::types
