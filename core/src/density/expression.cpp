// Density expressions: a recursive-descent parser, constant folding, and a small stack
// machine. See density.hpp for the language.
//
// Grammar, lowest precedence first (the conventions of muParser, which earlier versions
// used, so that existing requests keep their meaning):
//   ternary := or ( '?' ternary ':' ternary )?
//   or      := and ( '||' and )*
//   and     := cmp ( '&&' cmp )*
//   cmp     := add ( ('<' | '>' | '<=' | '>=' | '==' | '!=') add )*
//   add     := mul ( ('+' | '-') mul )*
//   mul     := unary ( ('*' | '/') unary )*
//   unary   := ('-' | '+') unary | power          so -x^2 = -(x^2)
//   power   := primary ( '^' unary )?             so 2^3^2 = 2^9 and 2^-1 = 0.5
//   primary := number | x | y | _pi | _e | name '(' ternary (',' ternary)* ')' | '(' ternary ')'

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <numbers>
#include <string_view>

#include "density/expression.hpp"

#include <vector>

#include "meshd/core/errors.hpp"
#include "meshd/core/vec2.hpp"

namespace meshd::core {

namespace {

enum class Op : std::uint8_t {
    Const, X, Y,
    Neg, Add, Sub, Mul, Div, Pow, Square,
    AddC, SubC, RSubC, MulC, DivC, RDivC,  // with the constant operand in the instruction
    Lt, Gt, Le, Ge, Eq, Ne, And, Or,
    Min, Max,
    Call1, Call2,
    JumpIfZero, Jump,
    Sqrt,    // a call of sqrt, without the call (made by emit only)
    Abs,     // a call of abs, the same
    MinC, MaxC,  // min and max with a constant second operand (emit only)
    LtC, GtC, LeC, GeC,  // comparisons with a constant second operand (emit only)
    Select,  // c ? a : b over a batch: both branches computed, one kept per point (batch code only)
};

using Fn1 = double (*)(double);
using Fn2 = double (*)(double, double);

struct Function {
    std::string_view name;
    int arity;  // -1: one or more (min, max, sum, avg)
    Fn1 f1;
    Fn2 f2;
};

double f_sqrt(double a) { return std::sqrt(a); }
double f_abs(double a) { return std::fabs(a); }
double f_exp(double a) { return std::exp(a); }
double f_log(double a) { return std::log(a); }
double f_log2(double a) { return std::log2(a); }
double f_log10(double a) { return std::log10(a); }
double f_sin(double a) { return std::sin(a); }
double f_cos(double a) { return std::cos(a); }
double f_tan(double a) { return std::tan(a); }
double f_asin(double a) { return std::asin(a); }
double f_acos(double a) { return std::acos(a); }
double f_atan(double a) { return std::atan(a); }
double f_sinh(double a) { return std::sinh(a); }
double f_cosh(double a) { return std::cosh(a); }
double f_tanh(double a) { return std::tanh(a); }
double f_floor(double a) { return std::floor(a); }
double f_ceil(double a) { return std::ceil(a); }
double f_rint(double a) { return std::rint(a); }
double f_sign(double a) { return a > 0.0 ? 1.0 : (a < 0.0 ? -1.0 : 0.0); }
double f_pow(double a, double b) { return std::pow(a, b); }
double f_atan2(double a, double b) { return std::atan2(a, b); }

constexpr std::array<Function, 26> kFunctions{{
    {"sqrt", 1, f_sqrt, nullptr},   {"abs", 1, f_abs, nullptr},     {"exp", 1, f_exp, nullptr},
    {"log", 1, f_log, nullptr},     {"ln", 1, f_log, nullptr},      {"log2", 1, f_log2, nullptr},
    {"log10", 1, f_log10, nullptr}, {"sin", 1, f_sin, nullptr},     {"cos", 1, f_cos, nullptr},
    {"tan", 1, f_tan, nullptr},     {"asin", 1, f_asin, nullptr},   {"acos", 1, f_acos, nullptr},
    {"atan", 1, f_atan, nullptr},   {"sinh", 1, f_sinh, nullptr},   {"cosh", 1, f_cosh, nullptr},
    {"tanh", 1, f_tanh, nullptr},   {"floor", 1, f_floor, nullptr}, {"ceil", 1, f_ceil, nullptr},
    {"rint", 1, f_rint, nullptr},   {"sign", 1, f_sign, nullptr},   {"pow", 2, nullptr, f_pow},
    {"atan2", 2, nullptr, f_atan2}, {"min", -1, nullptr, nullptr},  {"max", -1, nullptr, nullptr},
    {"sum", -1, nullptr, nullptr},  {"avg", -1, nullptr, nullptr},
}};

// The syntax tree, in one vector; children by index.
struct Node {
    Op op;
    double value = 0.0;  // Const
    const Function* fn = nullptr;
    int a = -1, b = -1, c = -1;  // operands (c: the else branch of a conditional)
};
constexpr Op kConditional = Op::JumpIfZero;  // a node with this op is `a ? b : c`

constexpr int kMaxNesting = 200;
constexpr size_t kMaxNodes = 10000;

class Parser {
public:
    explicit Parser(std::string_view text) : s_(text) {}

    int parse(std::vector<Node>& nodes) {
        nodes_ = &nodes;
        skip();
        if (pos_ == s_.size()) fail("the expression is empty");
        const int root = ternary();
        if (pos_ != s_.size()) fail_here("unexpected '" + std::string(1, s_[pos_]) + "'");
        return root;
    }

private:
    [[noreturn]] void fail(const std::string& what) const {
        throw GeometryError(GeometryErrorKind::DensityExpression, "cannot parse \"" + std::string(s_) + "\": " + what);
    }
    [[noreturn]] void fail_here(const std::string& what) const {
        if (pos_ >= s_.size()) fail(what + " at the end");
        fail(what + " at position " + std::to_string(pos_));
    }

    void skip() {
        while (pos_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[pos_]))) ++pos_;
    }
    bool accept(std::string_view tok) {
        if (s_.substr(pos_, tok.size()) != tok) return false;
        pos_ += tok.size();
        skip();
        return true;
    }
    void expect(std::string_view tok) {
        if (!accept(tok)) fail_here("expected '" + std::string(tok) + "'");
    }

    int add(Node n) {
        // The tree is folded and compiled recursively: bound its size (and so its depth).
        if (nodes_->size() >= kMaxNodes) fail("longer than " + std::to_string(kMaxNodes) + " terms");
        nodes_->push_back(n);
        return static_cast<int>(nodes_->size()) - 1;
    }
    int binary(Op op, int a, int b) { return add({op, 0.0, nullptr, a, b, -1}); }

    struct Depth {
        explicit Depth(Parser& p) : p_(p) {
            if (++p_.depth_ > kMaxNesting) p_.fail_here("nesting deeper than " + std::to_string(kMaxNesting) + " levels");
        }
        ~Depth() { --p_.depth_; }
        Parser& p_;
    };

    int ternary() {
        Depth guard(*this);
        const int cond = logical_or();
        if (!accept("?")) return cond;
        const int yes = ternary();
        expect(":");
        const int no = ternary();
        return add({kConditional, 0.0, nullptr, cond, yes, no});
    }
    int logical_or() {
        int l = logical_and();
        while (accept("||")) l = binary(Op::Or, l, logical_and());
        return l;
    }
    int logical_and() {
        int l = comparison();
        while (accept("&&")) l = binary(Op::And, l, comparison());
        return l;
    }
    int comparison() {
        int l = additive();
        for (;;) {
            if (accept("<=")) l = binary(Op::Le, l, additive());
            else if (accept(">=")) l = binary(Op::Ge, l, additive());
            else if (accept("==")) l = binary(Op::Eq, l, additive());
            else if (accept("!=")) l = binary(Op::Ne, l, additive());
            else if (accept("<")) l = binary(Op::Lt, l, additive());
            else if (accept(">")) l = binary(Op::Gt, l, additive());
            else return l;
        }
    }
    int additive() {
        int l = multiplicative();
        for (;;) {
            if (accept("+")) l = binary(Op::Add, l, multiplicative());
            else if (accept("-")) l = binary(Op::Sub, l, multiplicative());
            else return l;
        }
    }
    int multiplicative() {
        int l = unary();
        for (;;) {
            if (accept("*")) l = binary(Op::Mul, l, unary());
            else if (accept("/")) l = binary(Op::Div, l, unary());
            else return l;
        }
    }
    int unary() {
        Depth guard(*this);
        if (accept("-")) return add({Op::Neg, 0.0, nullptr, unary(), -1, -1});
        if (accept("+")) return unary();
        return power();
    }
    int power() {
        const int base = primary();
        if (!accept("^")) return base;
        return binary(Op::Pow, base, unary());
    }
    int primary() {
        if (pos_ >= s_.size()) fail("unexpected end of the expression");
        const char ch = s_[pos_];
        if (std::isdigit(static_cast<unsigned char>(ch)) || ch == '.') return number();
        if (std::isalpha(static_cast<unsigned char>(ch)) || ch == '_') return name();
        if (accept("(")) {
            const int inner = ternary();
            expect(")");
            return inner;
        }
        fail_here("unexpected '" + std::string(1, ch) + "'");
    }
    int number() {
        const size_t start = pos_;
        while (pos_ < s_.size() && (std::isdigit(static_cast<unsigned char>(s_[pos_])) || s_[pos_] == '.')) ++pos_;
        if (pos_ < s_.size() && (s_[pos_] == 'e' || s_[pos_] == 'E')) {
            size_t p = pos_ + 1;
            if (p < s_.size() && (s_[p] == '+' || s_[p] == '-')) ++p;
            if (p < s_.size() && std::isdigit(static_cast<unsigned char>(s_[p]))) {
                pos_ = p;
                while (pos_ < s_.size() && std::isdigit(static_cast<unsigned char>(s_[pos_]))) ++pos_;
            }
        }
        const std::string text(s_.substr(start, pos_ - start));
        char* end = nullptr;
        const double v = std::strtod(text.c_str(), &end);
        if (end != text.c_str() + text.size()) {
            pos_ = start;
            fail_here("malformed number '" + text + "'");
        }
        skip();
        return add({Op::Const, v});
    }
    int name() {
        const size_t start = pos_;
        while (pos_ < s_.size() && (std::isalnum(static_cast<unsigned char>(s_[pos_])) || s_[pos_] == '_')) ++pos_;
        const std::string_view id = s_.substr(start, pos_ - start);
        skip();
        if (id == "x") return add({Op::X});
        if (id == "y") return add({Op::Y});
        if (id == "_pi") return add({Op::Const, std::numbers::pi});
        if (id == "_e") return add({Op::Const, std::numbers::e});
        const Function* fn = nullptr;
        for (const Function& f : kFunctions)
            if (f.name == id) fn = &f;
        if (!fn) {
            pos_ = start;
            fail_here("unknown name '" + std::string(id) + "' (variables are x and y)");
        }
        if (!accept("(")) fail_here("expected '(' after " + std::string(id));
        std::vector<int> args{ternary()};
        while (accept(",")) args.push_back(ternary());
        expect(")");
        if (fn->arity > 0 && static_cast<int>(args.size()) != fn->arity) {
            pos_ = start;
            fail_here(std::string(id) + " takes " + std::to_string(fn->arity) + " argument" + (fn->arity > 1 ? "s" : "") +
                      ", not " + std::to_string(args.size()));
        }
        if (fn->arity == 1) return add({Op::Call1, 0.0, fn, args[0]});
        if (fn->arity == 2) return add({Op::Call2, 0.0, fn, args[0], args[1]});
        // Variadic: a chain of binary nodes.
        const Op op = fn->name == "min" ? Op::Min : (fn->name == "max" ? Op::Max : Op::Add);
        int acc = args[0];
        for (size_t i = 1; i < args.size(); ++i) acc = binary(op, acc, args[i]);
        if (fn->name == "avg") acc = binary(Op::Div, acc, add({Op::Const, static_cast<double>(args.size())}));
        return acc;
    }

    std::string_view s_;
    size_t pos_ = 0;
    int depth_ = 0;
    std::vector<Node>* nodes_ = nullptr;
};

double apply(Op op, double a, double b) {
    switch (op) {
        case Op::Add: return a + b;
        case Op::Sub: return a - b;
        case Op::Mul: return a * b;
        case Op::Div: return a / b;
        case Op::Pow: return std::pow(a, b);
        case Op::Lt: return a < b ? 1.0 : 0.0;
        case Op::Gt: return a > b ? 1.0 : 0.0;
        case Op::Le: return a <= b ? 1.0 : 0.0;
        case Op::Ge: return a >= b ? 1.0 : 0.0;
        case Op::Eq: return a == b ? 1.0 : 0.0;
        case Op::Ne: return a != b ? 1.0 : 0.0;
        case Op::And: return a != 0.0 && b != 0.0 ? 1.0 : 0.0;
        case Op::Or: return a != 0.0 || b != 0.0 ? 1.0 : 0.0;
        case Op::Min: return std::fmin(a, b);
        case Op::Max: return std::fmax(a, b);
        default: return std::nan("");
    }
}

bool is_binary(Op op) {
    switch (op) {
        case Op::Add: case Op::Sub: case Op::Mul: case Op::Div: case Op::Pow: case Op::Lt: case Op::Gt:
        case Op::Le: case Op::Ge: case Op::Eq: case Op::Ne: case Op::And: case Op::Or: case Op::Min: case Op::Max:
            return true;
        default:
            return false;
    }
}

}  // namespace

// The compiled program: postfix instructions over a value stack of known depth.
struct Expression::Impl {
    struct Instr {
        Op op;
        std::int32_t target = 0;  // jumps
        double value = 0.0;       // Const and the ...C forms
        const Function* fn = nullptr;
    };
    std::string text;
    std::vector<Instr> code;
    // The same program for batches (run_batch): a conditional computes both branches and
    // keeps one per point (Select), as a batch cannot jump per point. Empty when its deeper
    // stack does not fit; batches then run point by point.
    std::vector<Instr> batch_code;
    int depth = 0;
    bool selecting = false;  // emit() writes the batch code: conditionals as Select

    static constexpr int kMaxStack = 64;
    static constexpr size_t kBatch = 32;

    explicit Impl(std::string t) : text(std::move(t)) {
        std::vector<Node> nodes;
        const int root = Parser(text).parse(nodes);
        fold(nodes, root);
        int sp = 0;
        emit(nodes, root, sp);
        if (depth > kMaxStack)
            throw GeometryError(GeometryErrorKind::DensityExpression,
                                "cannot parse \"" + text + "\": the expression needs more than " +
                                    std::to_string(kMaxStack) + " intermediate values");
        std::vector<Instr> scalar;
        scalar.swap(code);
        const int scalar_depth = depth;
        depth = 0;
        sp = 0;
        selecting = true;
        emit(nodes, root, sp);
        if (depth <= kMaxStack) batch_code.swap(code);
        code.swap(scalar);
        depth = scalar_depth;
        selecting = false;
    }

    // Constant folding, bottom up; x^2 becomes a square.
    static void fold(std::vector<Node>& n, int i) {
        Node& node = n[static_cast<size_t>(i)];
        for (int k : {node.a, node.b, node.c})
            if (k >= 0) fold(n, k);
        auto is_const = [&](int k) { return k >= 0 && n[static_cast<size_t>(k)].op == Op::Const; };
        auto value = [&](int k) { return n[static_cast<size_t>(k)].value; };
        Node& m = n[static_cast<size_t>(i)];
        if (m.op == Op::Neg && is_const(m.a)) m = {Op::Const, -value(m.a)};
        else if (m.op == Op::Call1 && is_const(m.a)) m = {Op::Const, m.fn->f1(value(m.a))};
        else if (m.op == Op::Call2 && is_const(m.a) && is_const(m.b)) m = {Op::Const, m.fn->f2(value(m.a), value(m.b))};
        else if (is_binary(m.op) && is_const(m.a) && is_const(m.b)) m = {Op::Const, apply(m.op, value(m.a), value(m.b))};
        else if (m.op == kConditional && is_const(m.a)) m = n[static_cast<size_t>(value(m.a) != 0.0 ? m.b : m.c)];
        else if (m.op == Op::Pow && is_const(m.b) && value(m.b) == 2.0) m = {Op::Square, 0.0, nullptr, m.a};
    }

    void push(Instr in, int& sp, int delta) {
        code.push_back(in);
        sp += delta;
        depth = std::max(depth, sp);
    }

    void emit(const std::vector<Node>& n, int i, int& sp) {
        const Node& node = n[static_cast<size_t>(i)];
        auto is_const = [&](int k) { return n[static_cast<size_t>(k)].op == Op::Const; };
        auto value = [&](int k) { return n[static_cast<size_t>(k)].value; };
        switch (node.op) {
            case Op::Const: push({Op::Const, 0, node.value}, sp, 1); return;
            case Op::X: push({Op::X}, sp, 1); return;
            case Op::Y: push({Op::Y}, sp, 1); return;
            case Op::Neg: case Op::Square: case Op::Call1:
                emit(n, node.a, sp);
                if (node.op == Op::Call1 && node.fn->f1 == f_sqrt) push({Op::Sqrt}, sp, 0);
                else if (node.op == Op::Call1 && node.fn->f1 == f_abs) push({Op::Abs}, sp, 0);
                else push({node.op, 0, 0.0, node.fn}, sp, 0);
                return;
            case Op::Call2:
                emit(n, node.a, sp);
                emit(n, node.b, sp);
                push({Op::Call2, 0, 0.0, node.fn}, sp, -1);
                return;
            case kConditional: {
                if (selecting) {
                    emit(n, node.a, sp);
                    emit(n, node.b, sp);
                    emit(n, node.c, sp);
                    push({Op::Select}, sp, -2);
                    return;
                }
                emit(n, node.a, sp);
                const size_t jz = code.size();
                push({Op::JumpIfZero}, sp, -1);
                emit(n, node.b, sp);
                const size_t jmp = code.size();
                push({Op::Jump}, sp, -1);  // the else branch pushes the same slot again
                code[jz].target = static_cast<std::int32_t>(code.size());
                emit(n, node.c, sp);
                code[jmp].target = static_cast<std::int32_t>(code.size());
                return;
            }
            default: break;
        }
        // Binary: an operand that is a constant rides in the instruction.
        if (is_const(node.b) && (node.op == Op::Add || node.op == Op::Sub || node.op == Op::Mul || node.op == Op::Div)) {
            emit(n, node.a, sp);
            const Op op = node.op == Op::Add ? Op::AddC : node.op == Op::Sub ? Op::SubC : node.op == Op::Mul ? Op::MulC : Op::DivC;
            push({op, 0, value(node.b)}, sp, 0);
            return;
        }
        // (Only a second operand for min and max: of two equal zeros they give the second.)
        if (is_const(node.b) && (node.op == Op::Min || node.op == Op::Max)) {
            emit(n, node.a, sp);
            push({node.op == Op::Min ? Op::MinC : Op::MaxC, 0, value(node.b)}, sp, 0);
            return;
        }
        if (is_const(node.b) && (node.op == Op::Lt || node.op == Op::Gt || node.op == Op::Le || node.op == Op::Ge)) {
            emit(n, node.a, sp);
            const Op op = node.op == Op::Lt ? Op::LtC : node.op == Op::Gt ? Op::GtC : node.op == Op::Le ? Op::LeC : Op::GeC;
            push({op, 0, value(node.b)}, sp, 0);
            return;
        }
        if (is_const(node.a) && (node.op == Op::Add || node.op == Op::Sub || node.op == Op::Mul || node.op == Op::Div)) {
            emit(n, node.b, sp);
            const Op op = node.op == Op::Add ? Op::AddC : node.op == Op::Sub ? Op::RSubC : node.op == Op::Mul ? Op::MulC : Op::RDivC;
            push({op, 0, value(node.a)}, sp, 0);
            return;
        }
        emit(n, node.a, sp);
        emit(n, node.b, sp);
        push({node.op}, sp, -1);
    }

    // run() over n <= kBatch points: each instruction once for all of them.
    void run_batch(const double* x, const double* y, double* out, size_t n) const {
        std::array<std::array<double, kBatch>, kMaxStack> st;
        int sp = -1;
        auto top = [&](int i) -> double* { return st[static_cast<size_t>(i)].data(); };
        for (const Instr& in : batch_code) {
            switch (in.op) {
                case Op::Const: { double* t = top(++sp); for (size_t i = 0; i < n; ++i) t[i] = in.value; break; }
                case Op::X: { double* t = top(++sp); for (size_t i = 0; i < n; ++i) t[i] = x[i]; break; }
                case Op::Y: { double* t = top(++sp); for (size_t i = 0; i < n; ++i) t[i] = y[i]; break; }
                case Op::Neg: { double* t = top(sp); for (size_t i = 0; i < n; ++i) t[i] = -t[i]; break; }
                case Op::Square: { double* t = top(sp); for (size_t i = 0; i < n; ++i) t[i] *= t[i]; break; }
                case Op::AddC: { double* t = top(sp); for (size_t i = 0; i < n; ++i) t[i] += in.value; break; }
                case Op::SubC: { double* t = top(sp); for (size_t i = 0; i < n; ++i) t[i] -= in.value; break; }
                case Op::RSubC: { double* t = top(sp); for (size_t i = 0; i < n; ++i) t[i] = in.value - t[i]; break; }
                case Op::MulC: { double* t = top(sp); for (size_t i = 0; i < n; ++i) t[i] *= in.value; break; }
                case Op::DivC: { double* t = top(sp); for (size_t i = 0; i < n; ++i) t[i] /= in.value; break; }
                case Op::RDivC: { double* t = top(sp); for (size_t i = 0; i < n; ++i) t[i] = in.value / t[i]; break; }
                case Op::Sqrt: { double* t = top(sp); for (size_t i = 0; i < n; ++i) t[i] = std::sqrt(t[i]); break; }
                case Op::Abs: { double* t = top(sp); for (size_t i = 0; i < n; ++i) t[i] = std::fabs(t[i]); break; }
                case Op::MinC: { double* t = top(sp); for (size_t i = 0; i < n; ++i) t[i] = fmin_inline(t[i], in.value); break; }
                case Op::MaxC: { double* t = top(sp); for (size_t i = 0; i < n; ++i) t[i] = fmax_inline(t[i], in.value); break; }
                case Op::LtC: { double* t = top(sp); for (size_t i = 0; i < n; ++i) t[i] = t[i] < in.value ? 1.0 : 0.0; break; }
                case Op::GtC: { double* t = top(sp); for (size_t i = 0; i < n; ++i) t[i] = t[i] > in.value ? 1.0 : 0.0; break; }
                case Op::LeC: { double* t = top(sp); for (size_t i = 0; i < n; ++i) t[i] = t[i] <= in.value ? 1.0 : 0.0; break; }
                case Op::GeC: { double* t = top(sp); for (size_t i = 0; i < n; ++i) t[i] = t[i] >= in.value ? 1.0 : 0.0; break; }
                case Op::Lt: { --sp; double* t = top(sp); const double* u = top(sp + 1); for (size_t i = 0; i < n; ++i) t[i] = t[i] < u[i] ? 1.0 : 0.0; break; }
                case Op::Gt: { --sp; double* t = top(sp); const double* u = top(sp + 1); for (size_t i = 0; i < n; ++i) t[i] = t[i] > u[i] ? 1.0 : 0.0; break; }
                case Op::Le: { --sp; double* t = top(sp); const double* u = top(sp + 1); for (size_t i = 0; i < n; ++i) t[i] = t[i] <= u[i] ? 1.0 : 0.0; break; }
                case Op::Ge: { --sp; double* t = top(sp); const double* u = top(sp + 1); for (size_t i = 0; i < n; ++i) t[i] = t[i] >= u[i] ? 1.0 : 0.0; break; }
                case Op::And: { --sp; double* t = top(sp); const double* u = top(sp + 1); for (size_t i = 0; i < n; ++i) t[i] = t[i] != 0.0 && u[i] != 0.0 ? 1.0 : 0.0; break; }
                case Op::Or: { --sp; double* t = top(sp); const double* u = top(sp + 1); for (size_t i = 0; i < n; ++i) t[i] = t[i] != 0.0 || u[i] != 0.0 ? 1.0 : 0.0; break; }
                case Op::Min: { --sp; double* t = top(sp); const double* u = top(sp + 1); for (size_t i = 0; i < n; ++i) t[i] = fmin_inline(t[i], u[i]); break; }
                case Op::Max: { --sp; double* t = top(sp); const double* u = top(sp + 1); for (size_t i = 0; i < n; ++i) t[i] = fmax_inline(t[i], u[i]); break; }
                case Op::Call1: { double* t = top(sp); for (size_t i = 0; i < n; ++i) t[i] = in.fn->f1(t[i]); break; }
                case Op::Call2: {
                    --sp;
                    double* t = top(sp);
                    const double* u = top(sp + 1);
                    for (size_t i = 0; i < n; ++i) t[i] = in.fn->f2(t[i], u[i]);
                    break;
                }
                case Op::Select: {
                    sp -= 2;
                    double* t = top(sp);
                    const double *yes = top(sp + 1), *no = top(sp + 2);
                    // As run()'s JumpIfZero: the first branch unless the condition is 0.
                    for (size_t i = 0; i < n; ++i) t[i] = t[i] == 0.0 ? no[i] : yes[i];
                    break;
                }
                case Op::Add: { --sp; double* t = top(sp); const double* u = top(sp + 1); for (size_t i = 0; i < n; ++i) t[i] += u[i]; break; }
                case Op::Sub: { --sp; double* t = top(sp); const double* u = top(sp + 1); for (size_t i = 0; i < n; ++i) t[i] -= u[i]; break; }
                case Op::Mul: { --sp; double* t = top(sp); const double* u = top(sp + 1); for (size_t i = 0; i < n; ++i) t[i] *= u[i]; break; }
                case Op::Div: { --sp; double* t = top(sp); const double* u = top(sp + 1); for (size_t i = 0; i < n; ++i) t[i] /= u[i]; break; }
                default: {
                    --sp;
                    double* t = top(sp);
                    const double* u = top(sp + 1);
                    for (size_t i = 0; i < n; ++i) t[i] = apply(in.op, t[i], u[i]);
                    break;
                }
            }
        }
        for (size_t i = 0; i < n; ++i) out[i] = st[0][i];
    }

    // The value on top of the stack is kept apart from those below it (in a register, where
    // the stack itself is memory): an instruction on the top alone touches no memory, a push
    // stores the old top, a binary operator takes its first operand from below.
    double run(double x, double y) const {
        std::array<double, kMaxStack> below;
        double top = 0.0;
        int sp = -1;  // index of the value below the top
        auto push = [&](double v) {
            below[static_cast<size_t>(++sp)] = top;
            top = v;
        };
        auto pop = [&]() { return below[static_cast<size_t>(sp--)]; };
        const Instr* const begin = code.data();
        const Instr* const end = begin + code.size();
        for (const Instr* in = begin; in != end; ++in) {
            switch (in->op) {
                case Op::Const: push(in->value); break;
                case Op::X: push(x); break;
                case Op::Y: push(y); break;
                case Op::Neg: top = -top; break;
                case Op::Square: top *= top; break;
                case Op::AddC: top += in->value; break;
                case Op::SubC: top -= in->value; break;
                case Op::RSubC: top = in->value - top; break;
                case Op::MulC: top *= in->value; break;
                case Op::DivC: top /= in->value; break;
                case Op::RDivC: top = in->value / top; break;
                case Op::Sqrt: top = std::sqrt(top); break;
                case Op::Abs: top = std::fabs(top); break;
                case Op::MinC: top = fmin_inline(top, in->value); break;
                case Op::MaxC: top = fmax_inline(top, in->value); break;
                case Op::LtC: top = top < in->value ? 1.0 : 0.0; break;
                case Op::GtC: top = top > in->value ? 1.0 : 0.0; break;
                case Op::LeC: top = top <= in->value ? 1.0 : 0.0; break;
                case Op::GeC: top = top >= in->value ? 1.0 : 0.0; break;
                case Op::Call1: top = in->fn->f1(top); break;
                // The commonest binary operators without apply()'s second dispatch.
                case Op::Add: top = pop() + top; break;
                case Op::Sub: top = pop() - top; break;
                case Op::Mul: top = pop() * top; break;
                case Op::Div: top = pop() / top; break;
                case Op::Lt: top = pop() < top ? 1.0 : 0.0; break;
                case Op::Gt: top = pop() > top ? 1.0 : 0.0; break;
                case Op::Le: top = pop() <= top ? 1.0 : 0.0; break;
                case Op::Ge: top = pop() >= top ? 1.0 : 0.0; break;
                case Op::And: { const double a = pop(); top = a != 0.0 && top != 0.0 ? 1.0 : 0.0; break; }
                case Op::Or: { const double a = pop(); top = a != 0.0 || top != 0.0 ? 1.0 : 0.0; break; }
                // libm's fmin and fmax to the bit, without the call (vec2.hpp).
                case Op::Min: top = fmin_inline(pop(), top); break;
                case Op::Max: top = fmax_inline(pop(), top); break;
                case Op::Call2: top = in->fn->f2(pop(), top); break;
                case Op::JumpIfZero: {
                    const double condition = top;
                    top = pop();
                    if (condition == 0.0) in = begin + in->target - 1;
                    break;
                }
                case Op::Jump: in = begin + in->target - 1; break;
                default: top = apply(in->op, pop(), top); break;
            }
        }
        return top;
    }
};

Expression::Expression(const std::string& text) : impl_(std::make_unique<Impl>(text)) {}
Expression::Expression(const Expression& other) : impl_(std::make_unique<Impl>(*other.impl_)) {}
Expression& Expression::operator=(const Expression& other) {
    if (this != &other) impl_ = std::make_unique<Impl>(*other.impl_);
    return *this;
}
Expression::Expression(Expression&&) noexcept = default;
Expression& Expression::operator=(Expression&&) noexcept = default;
Expression::~Expression() = default;

double Expression::operator()(double x, double y) const { return impl_->run(x, y); }

void Expression::evaluate(const double* x, const double* y, double* out, size_t n) const {
    if (impl_->batch_code.empty()) {
        for (size_t i = 0; i < n; ++i) out[i] = impl_->run(x[i], y[i]);
        return;
    }
    for (size_t i = 0; i < n; i += Impl::kBatch)
        impl_->run_batch(x + i, y + i, out + i, std::min(Impl::kBatch, n - i));
}

const std::string& Expression::text() const { return impl_->text; }

}  // namespace meshd::core
