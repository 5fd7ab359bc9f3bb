#include "types/idl_parser.hpp"

#include <charconv>
#include <limits>
#include <optional>

#include "base/config_error.hpp"
#include "types/type_library.hpp"

namespace tgw::types {

namespace {

using Kind = IdlType::Kind;

/// An annotation as written: its name (the last component of a scoped one) and where its arguments are in the
/// token list, so that they are evaluated like any constant expression.
struct Annotation {
    std::string name;
    std::size_t args_begin = 0;  ///< the first token after '('
    std::size_t args_end = 0;    ///< the ')'; equal to args_begin without arguments
};

class Parser {
  public:
    Parser(IdlTokens tokens, const std::string& file, TypeLibrary& library, std::size_t source)
        : tokens_(std::move(tokens.tokens)), file_(file), library_(library), source_(source) {}

    void run() { definitions(false); }

  private:
    // ---- tokens

    const IdlToken& peek(std::size_t ahead = 0) const { return tokens_[std::min(pos_ + ahead, tokens_.size() - 1)]; }

    const IdlToken& next() {
        const IdlToken& token = tokens_[pos_];
        if (pos_ + 1 < tokens_.size())
            ++pos_;
        return token;
    }

    bool at(const char* text, std::size_t ahead = 0) const {
        const IdlToken& token = peek(ahead);
        return (token.kind == IdlToken::Kind::identifier || token.kind == IdlToken::Kind::punctuation) &&
               token.text == text;
    }

    bool accept(const char* text) {
        if (!at(text))
            return false;
        next();
        return true;
    }

    static std::string describe(const IdlToken& token) {
        switch (token.kind) {
            case IdlToken::Kind::end:
                return "the end of the file";
            case IdlToken::Kind::string:
                return "a string literal";
            case IdlToken::Kind::character:
                return "a character literal";
            default:
                return "'" + token.text + "'";
        }
    }

    [[noreturn]] void fail(const std::string& what) const { fail_at(what, peek().line); }

    [[noreturn]] void fail_at(const std::string& what, int line) const {
        throw base::ConfigError(file_ + ":" + std::to_string(line) + ": " + what);
    }

    void expect(const char* text, const char* context) {
        if (!accept(text))
            fail(std::string("expected '") + text + "' " + context + ", found " + describe(peek()));
    }

    std::string identifier(const char* what) {
        if (peek().kind != IdlToken::Kind::identifier)
            fail(std::string("expected ") + what + ", found " + describe(peek()));
        return next().text;
    }

    IdlLocation here() const { return {file_, peek().line}; }

    std::string scope_text() const {
        std::string text;
        for (const std::string& part : scope_)
            text += (text.empty() ? "" : "::") + part;
        return text;
    }

    std::string scoped(const std::string& name) const { return scope_.empty() ? name : scope_text() + "::" + name; }

    std::string scoped_name() {
        std::string name;
        if (accept("::"))
            name = "::";
        name += identifier("a name");
        while (accept("::"))
            name += "::" + identifier("a name after '::'");
        return name;
    }

    // ---- declarations

    void definitions(bool in_module) {
        while (true) {
            if (peek().kind == IdlToken::Kind::end) {
                if (in_module)
                    fail("expected '}' to close the module, found the end of the file");
                return;
            }
            if (in_module && at("}"))
                return;
            definition();
        }
    }

    void definition() {
        const std::vector<Annotation> annotations = parse_annotations();
        if (accept(";"))
            return;
        if (peek().kind != IdlToken::Kind::identifier)
            fail("expected a declaration (module, struct, enum, typedef, const), found " + describe(peek()));
        const std::string keyword = peek().text;
        if (keyword == "module") {
            module();
        } else if (keyword == "struct") {
            structure(annotations);
        } else if (keyword == "enum") {
            enumeration(annotations);
        } else if (keyword == "typedef") {
            type_definition();
        } else if (keyword == "const") {
            constant();
        } else if (keyword == "union" || keyword == "bitset" || keyword == "bitmask") {
            skip_unsupported(keyword);
        } else {
            fail("expected a declaration (module, struct, enum, typedef, const), found " + describe(peek()));
        }
    }

    void module() {
        next();
        scope_.push_back(identifier("a module name"));
        expect("{", "after the module name");
        definitions(true);
        expect("}", "to close the module");
        expect(";", "after the module's '}'");
        scope_.pop_back();
    }

    void structure(const std::vector<Annotation>& annotations) {
        next();
        IdlStruct declared;
        declared.where = here();
        declared.name = scoped(identifier("a struct name"));
        if (accept(";"))
            return;  // a forward declaration: the definition follows
        declared.extensibility = extensibility(annotations);
        declared.topic = flag(annotations, "topic").value_or(false);
        if (accept(":")) {
            IdlType base;
            base.kind = Kind::named;
            base.where = here();
            base.scope = scope_text();
            base.name = scoped_name();
            declared.base = std::move(base);
        }
        expect("{", "to open the struct");
        while (!accept("}")) {
            if (peek().kind == IdlToken::Kind::end)
                fail("expected '}' to close struct " + declared.name + ", found the end of the file");
            member(declared);
        }
        expect(";", "after the struct's '}'");
        library_.declare(std::move(declared), source_);
    }

    void member(IdlStruct& into) {
        const std::vector<Annotation> annotations = parse_annotations();
        const IdlType type = type_spec();
        do {
            IdlMember declared;
            declared.name = identifier("a member name");
            declared.type = array_of(type);
            declared.key = flag(annotations, "key").value_or(false);
            declared.optional = flag(annotations, "optional").value_or(false);
            if (const Annotation* id = find(annotations, "id"))
                declared.id = static_cast<std::uint32_t>(annotation_integer(*id, 0, 0x0fffffff));
            into.members.push_back(std::move(declared));
        } while (accept(","));
        expect(";", "after the member");
    }

    void enumeration(const std::vector<Annotation>& annotations) {
        next();
        IdlEnum declared;
        declared.where = here();
        declared.name = scoped(identifier("an enum name"));
        if (const Annotation* bits = find(annotations, "bit_bound"))
            declared.bit_bound = static_cast<std::uint32_t>(annotation_integer(*bits, 1, 32));
        expect("{", "to open the enum");
        std::int64_t value = 0;
        do {
            const std::vector<Annotation> enumerator_annotations = parse_annotations();
            IdlEnumerator enumerator;
            enumerator.name = identifier("an enumerator");
            if (const Annotation* given = find(enumerator_annotations, "value"))
                value = annotation_integer(*given, std::numeric_limits<std::int32_t>::min(),
                                           std::numeric_limits<std::int32_t>::max());
            if (value > std::numeric_limits<std::int32_t>::max())
                fail("enumerator " + enumerator.name + " is beyond 32 bits");
            enumerator.value = static_cast<std::int32_t>(value++);
            declared.enumerators.push_back(std::move(enumerator));
        } while (accept(","));
        expect("}", "to close the enum");
        expect(";", "after the enum's '}'");
        library_.declare(std::move(declared), source_);
    }

    void type_definition() {
        next();
        const IdlType type = type_spec();
        do {
            IdlTypedef declared;
            declared.where = here();
            declared.name = scoped(identifier("the typedef's name"));
            declared.type = array_of(type);
            library_.declare(std::move(declared), source_);
        } while (accept(","));
        expect(";", "after the typedef");
    }

    /// Integer constants are kept for bounds; others (string, float, boolean) are read and dropped.
    void constant() {
        next();
        const IdlType type = type_spec();
        const std::string name = scoped(identifier("the constant's name"));
        expect("=", "after the constant's name");
        const bool integral = type.primitive_size() > 0 && type.kind != Kind::float32 && type.kind != Kind::float64 &&
                              type.kind != Kind::boolean && type.kind != Kind::char8;
        if (integral || (type.kind == Kind::named && integer_expression_ahead())) {
            library_.declare_constant(name, const_expr("the constant " + name));
        } else {
            while (!at(";") && peek().kind != IdlToken::Kind::end)
                next();
        }
        expect(";", "after the constant");
    }

    void skip_unsupported(const std::string& what) {
        next();
        IdlUnsupported declared;
        declared.where = here();
        declared.what = what;
        declared.name = scoped(identifier("a name"));
        if (accept(";"))
            return;
        while (!at("{")) {
            if (peek().kind == IdlToken::Kind::end)
                fail("expected '{' in " + what + " " + declared.name);
            next();
        }
        skip_balanced("{", "}");
        expect(";", ("after the " + what + "'s '}'").c_str());
        library_.declare(std::move(declared), source_);
    }

    /// Skips from an opening token to its matching closing one, both included.
    void skip_balanced(const char* open, const char* close) {
        const int line = peek().line;
        int depth = 0;
        do {
            if (peek().kind == IdlToken::Kind::end)
                fail_at(std::string("'") + open + "' is never closed", line);
            if (at(open))
                ++depth;
            else if (at(close))
                --depth;
            next();
        } while (depth > 0);
    }

    // ---- types

    IdlType type_spec() {
        IdlType type;
        type.where = here();
        if (at("::")) {
            return named(std::move(type));
        }
        if (peek().kind != IdlToken::Kind::identifier)
            fail("expected a type, found " + describe(peek()));
        const std::string word = peek().text;
        static const std::pair<const char*, Kind> SIMPLE[] = {
            {"boolean", Kind::boolean}, {"char", Kind::char8},     {"octet", Kind::octet},   {"int8", Kind::int8},
            {"uint8", Kind::uint8},     {"int16", Kind::int16},    {"uint16", Kind::uint16}, {"int32", Kind::int32},
            {"uint32", Kind::uint32},   {"int64", Kind::int64},    {"uint64", Kind::uint64}, {"short", Kind::int16},
            {"float", Kind::float32},   {"double", Kind::float64},
        };
        for (const auto& [name, kind] : SIMPLE) {
            if (word == name) {
                next();
                type.kind = kind;
                return type;
            }
        }
        if (word == "long") {
            next();
            type.kind = accept("long") ? Kind::int64 : Kind::int32;
            if (type.kind == Kind::int32 && accept("double"))
                return unsupported(std::move(type), "long double");
            return type;
        }
        if (word == "unsigned") {
            next();
            if (accept("short")) {
                type.kind = Kind::uint16;
            } else if (accept("long")) {
                type.kind = accept("long") ? Kind::uint64 : Kind::uint32;
            } else {
                fail("expected short or long after 'unsigned', found " + describe(peek()));
            }
            return type;
        }
        if (word == "string") {
            next();
            type.kind = Kind::string;
            if (accept("<")) {
                type.bound = bound("the string's bound");
                expect(">", "after the string's bound");
            }
            return type;
        }
        if (word == "sequence") {
            next();
            type.kind = Kind::sequence;
            expect("<", "after 'sequence'");
            type.element = std::make_shared<const IdlType>(type_spec());
            if (accept(","))
                type.bound = bound("the sequence's bound");
            expect(">", "to close the sequence");
            return type;
        }
        if (word == "wstring" || word == "fixed" || word == "map") {
            next();
            if (at("<"))
                skip_balanced("<", ">");
            return unsupported(std::move(type), word);
        }
        if (word == "wchar" || word == "any" || word == "Object" || word == "ValueBase") {
            next();
            return unsupported(std::move(type), word);
        }
        static const char* const NOT_TYPES[] = {"struct", "enum", "union", "module", "typedef", "const"};
        for (const char* keyword : NOT_TYPES) {
            if (word == keyword)
                fail("expected a type, found '" + word + "' (nested declarations are not supported)");
        }
        return named(std::move(type));
    }

    IdlType named(IdlType type) {
        type.kind = Kind::named;
        type.scope = scope_text();
        type.name = scoped_name();
        return type;
    }

    static IdlType unsupported(IdlType type, const std::string& what) {
        type.kind = Kind::unsupported;
        type.name = what;
        return type;
    }

    /// `base` with the array dimensions of a declarator that follow (`x[3][4]`), or as it is.
    IdlType array_of(const IdlType& base) {
        std::vector<std::uint32_t> dimensions;
        while (accept("[")) {
            dimensions.push_back(bound("the array's dimension"));
            expect("]", "after the array's dimension");
        }
        if (dimensions.empty())
            return base;
        IdlType array;
        array.kind = Kind::array;
        array.where = base.where;
        array.dimensions = std::move(dimensions);
        array.element = std::make_shared<const IdlType>(base);
        return array;
    }

    std::uint32_t bound(const std::string& what) {
        const int line = peek().line;
        const std::int64_t value = const_expr(what);
        if (value <= 0 || value > std::numeric_limits<std::uint32_t>::max())
            fail_at(what + " must be between 1 and 4294967295, not " + std::to_string(value), line);
        return static_cast<std::uint32_t>(value);
    }

    // ---- constant expressions: | ^ & + - * / % unary - + ~, parentheses, integer literals, constants

    /// True when the tokens up to ';' could be an integer expression (no string, float or character literal).
    bool integer_expression_ahead() const {
        for (std::size_t i = 0; !at(";", i) && peek(i).kind != IdlToken::Kind::end; ++i) {
            const IdlToken::Kind kind = peek(i).kind;
            if (kind == IdlToken::Kind::string || kind == IdlToken::Kind::floating ||
                kind == IdlToken::Kind::character || at("TRUE", i) || at("FALSE", i))
                return false;
        }
        return true;
    }

    std::int64_t const_expr(const std::string& what) {
        const int line = peek().line;
        std::string error;
        std::int64_t value = 0;
        if (!or_expr(value, error))
            fail_at(what + ": " + error, line);
        return value;
    }

    using Step = bool (Parser::*)(std::int64_t&, std::string&);

    bool binary(Step operand, std::initializer_list<const char*> operators, std::int64_t& value, std::string& error) {
        if (!(this->*operand)(value, error))
            return false;
        while (true) {
            const char* op = nullptr;
            for (const char* candidate : operators) {
                if (at(candidate))
                    op = candidate;
            }
            if (op == nullptr)
                return true;
            next();
            std::int64_t right = 0;
            if (!(this->*operand)(right, error))
                return false;
            if (!apply(*op, value, right, error))
                return false;
        }
    }

    static bool apply(char op, std::int64_t& left, std::int64_t right, std::string& error) {
        bool overflow = false;
        switch (op) {
            case '|':
                left |= right;
                break;
            case '^':
                left ^= right;
                break;
            case '&':
                left &= right;
                break;
            case '+':
                overflow = __builtin_add_overflow(left, right, &left);
                break;
            case '-':
                overflow = __builtin_sub_overflow(left, right, &left);
                break;
            case '*':
                overflow = __builtin_mul_overflow(left, right, &left);
                break;
            default:  // '/', '%'
                if (right == 0) {
                    error = "division by zero";
                    return false;
                }
                if (left == std::numeric_limits<std::int64_t>::min() && right == -1) {
                    overflow = true;
                    break;
                }
                left = op == '/' ? left / right : left % right;
        }
        if (overflow)
            error = "the value is beyond 64 bits";
        return !overflow;
    }

    bool or_expr(std::int64_t& v, std::string& e) { return binary(&Parser::xor_expr, {"|"}, v, e); }
    bool xor_expr(std::int64_t& v, std::string& e) { return binary(&Parser::and_expr, {"^"}, v, e); }
    bool and_expr(std::int64_t& v, std::string& e) { return binary(&Parser::add_expr, {"&"}, v, e); }
    bool add_expr(std::int64_t& v, std::string& e) { return binary(&Parser::mul_expr, {"+", "-"}, v, e); }
    bool mul_expr(std::int64_t& v, std::string& e) { return binary(&Parser::unary_expr, {"*", "/", "%"}, v, e); }

    bool unary_expr(std::int64_t& value, std::string& error) {
        if (accept("-")) {
            if (!unary_expr(value, error))
                return false;
            if (value == std::numeric_limits<std::int64_t>::min()) {
                error = "the value is beyond 64 bits";
                return false;
            }
            value = -value;
            return true;
        }
        if (accept("+"))
            return unary_expr(value, error);
        if (accept("~")) {
            if (!unary_expr(value, error))
                return false;
            value = ~value;
            return true;
        }
        return primary_expr(value, error);
    }

    bool primary_expr(std::int64_t& value, std::string& error) {
        if (accept("(")) {
            if (!or_expr(value, error))
                return false;
            if (!accept(")")) {
                error = "expected ')', found " + describe(peek());
                return false;
            }
            return true;
        }
        const IdlToken& token = peek();
        if (token.kind == IdlToken::Kind::integer) {
            next();
            return integer_literal(token.text, value, error);
        }
        if (token.kind == IdlToken::Kind::identifier || at("::")) {
            const std::string name = scoped_name();
            const std::optional<std::int64_t> known = library_.constant(name, scope_text());
            if (!known) {
                error = "'" + name + "' is not an integer constant declared before";
                return false;
            }
            value = *known;
            return true;
        }
        error = "expected an integer, found " + describe(token);
        return false;
    }

    static bool integer_literal(const std::string& text, std::int64_t& value, std::string& error) {
        int base = 10;
        std::size_t skip = 0;
        if (text.size() > 1 && text[0] == '0' && (text[1] == 'x' || text[1] == 'X')) {
            base = 16;
            skip = 2;
        } else if (text.size() > 1 && text[0] == '0') {
            base = 8;
            skip = 1;
        }
        std::uint64_t parsed = 0;
        const char* first = text.data() + skip;
        const char* last = text.data() + text.size();
        const auto [end, status] = std::from_chars(first, last, parsed, base);
        if (first == last || status != std::errc() || end != last ||
            parsed > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max())) {
            error = "'" + text + "' is not an integer of 63 bits";
            return false;
        }
        value = static_cast<std::int64_t>(parsed);
        return true;
    }

    // ---- annotations

    std::vector<Annotation> parse_annotations() {
        std::vector<Annotation> annotations;
        while (at("@")) {
            next();
            Annotation annotation;
            const std::string name = scoped_name();
            annotation.name = name.substr(name.rfind(':') == std::string::npos ? 0 : name.rfind(':') + 1);
            if (annotation.name == "annotation" && peek().kind == IdlToken::Kind::identifier && at("{", 1)) {
                // The declaration of an annotation: nothing of it changes the wire.
                next();
                skip_balanced("{", "}");
                expect(";", "after the annotation's '}'");
                continue;
            }
            annotation.args_begin = annotation.args_end = pos_;
            if (at("(")) {
                skip_balanced("(", ")");
                annotation.args_begin += 1;
                annotation.args_end = pos_ - 1;
            }
            annotations.push_back(annotation);
        }
        return annotations;
    }

    static const Annotation* find(const std::vector<Annotation>& annotations, const char* name) {
        for (const Annotation& annotation : annotations) {
            if (annotation.name == name)
                return &annotation;
        }
        return nullptr;
    }

    /// @key, @key(TRUE), @key(FALSE); nullopt when absent.
    std::optional<bool> flag(const std::vector<Annotation>& annotations, const char* name) const {
        const Annotation* annotation = find(annotations, name);
        if (annotation == nullptr)
            return std::nullopt;
        if (annotation->args_begin == annotation->args_end)
            return true;
        const IdlToken& value = tokens_[annotation->args_begin];
        if (annotation->args_end != annotation->args_begin + 1 ||
            (value.text != "TRUE" && value.text != "FALSE" && value.text != "true" && value.text != "false"))
            fail_at("@" + annotation->name + " takes TRUE or FALSE", value.line);
        return value.text == "TRUE" || value.text == "true";
    }

    std::int64_t annotation_integer(const Annotation& annotation, std::int64_t low, std::int64_t high) {
        const std::size_t resume = pos_;
        pos_ = annotation.args_begin;
        const int line = peek().line;
        if (annotation.args_begin == annotation.args_end)
            fail_at("@" + annotation.name + " needs a value", line);
        const std::int64_t value = const_expr("@" + annotation.name);
        if (pos_ != annotation.args_end)
            fail_at("@" + annotation.name + ": unexpected " + describe(peek()), line);
        if (value < low || value > high)
            fail_at("@" + annotation.name + " must be between " + std::to_string(low) + " and " + std::to_string(high),
                    line);
        pos_ = resume;
        return value;
    }

    IdlExtensibility extensibility(const std::vector<Annotation>& annotations) const {
        if (find(annotations, "final"))
            return IdlExtensibility::final;
        if (find(annotations, "appendable"))
            return IdlExtensibility::appendable;
        if (find(annotations, "mutable"))
            return IdlExtensibility::mutable_;
        if (const Annotation* given = find(annotations, "extensibility")) {
            const IdlToken& kind = tokens_[given->args_begin];
            if (given->args_end == given->args_begin + 1) {
                if (kind.text == "FINAL")
                    return IdlExtensibility::final;
                if (kind.text == "APPENDABLE")
                    return IdlExtensibility::appendable;
                if (kind.text == "MUTABLE")
                    return IdlExtensibility::mutable_;
            }
            fail_at("@extensibility takes FINAL, APPENDABLE or MUTABLE", kind.line);
        }
        return IdlExtensibility::unspecified;
    }

    std::vector<IdlToken> tokens_;
    std::size_t pos_ = 0;
    const std::string& file_;
    TypeLibrary& library_;
    const std::size_t source_;
    std::vector<std::string> scope_;
};

}  // namespace

void parse_idl(const std::string& text, const std::string& file, TypeLibrary& library,
               const IdlIncludeHandler& on_include) {
    IdlTokens tokens = tokenize_idl(text, file);
    if (on_include) {
        for (const IdlInclude& include : tokens.includes)
            on_include(include);
    }
    const std::size_t source = library.add_source(file, text);
    Parser(std::move(tokens), file, library, source).run();
}

}  // namespace tgw::types
