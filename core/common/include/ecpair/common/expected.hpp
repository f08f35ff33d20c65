#pragma once
// A small value-or-error type (C++20 has no std::expected). Accessing the
// wrong alternative is a programming error and aborts loudly.

#include <cstdio>
#include <cstdlib>
#include <optional>
#include <type_traits>
#include <utility>
#include <variant>

namespace ecpair {

template <class E>
class Unexpected {
public:
    explicit Unexpected(E error) : error_(std::move(error)) {}
    E& error() & { return error_; }
    const E& error() const& { return error_; }
    E&& error() && { return std::move(error_); }

private:
    E error_;
};

template <class E>
Unexpected<std::decay_t<E>> unexpected(E&& error) {
    return Unexpected<std::decay_t<E>>(std::forward<E>(error));
}

namespace detail {
[[noreturn]] inline void bad_expected_access(const char* what) {
    std::fprintf(stderr, "ecpair: bad Expected access: %s\n", what);
    std::abort();
}
}  // namespace detail

template <class T, class E>
class [[nodiscard]] Expected {
public:
    using value_type = T;
    using error_type = E;

    Expected()
        requires std::is_default_constructible_v<T>
        : storage_(std::in_place_index<0>) {}
    Expected(const T& value) : storage_(std::in_place_index<0>, value) {}  // NOLINT(implicit)
    Expected(T&& value) : storage_(std::in_place_index<0>, std::move(value)) {}  // NOLINT(implicit)
    template <class G>
    Expected(Unexpected<G> error)  // NOLINT(implicit)
        : storage_(std::in_place_index<1>, std::move(error).error()) {}

    bool has_value() const noexcept { return storage_.index() == 0; }
    explicit operator bool() const noexcept { return has_value(); }

    T& value() & {
        if (!has_value()) detail::bad_expected_access("value() on error");
        return std::get<0>(storage_);
    }
    const T& value() const& {
        if (!has_value()) detail::bad_expected_access("value() on error");
        return std::get<0>(storage_);
    }
    T&& value() && {
        if (!has_value()) detail::bad_expected_access("value() on error");
        return std::get<0>(std::move(storage_));
    }
    E& error() & {
        if (has_value()) detail::bad_expected_access("error() on value");
        return std::get<1>(storage_);
    }
    const E& error() const& {
        if (has_value()) detail::bad_expected_access("error() on value");
        return std::get<1>(storage_);
    }
    E&& error() && {
        if (has_value()) detail::bad_expected_access("error() on value");
        return std::get<1>(std::move(storage_));
    }

    T& operator*() & { return value(); }
    const T& operator*() const& { return value(); }
    T* operator->() { return &value(); }
    const T* operator->() const { return &value(); }

    template <class U>
    T value_or(U&& fallback) const& {
        return has_value() ? std::get<0>(storage_) : static_cast<T>(std::forward<U>(fallback));
    }

private:
    std::variant<T, E> storage_;
};

template <class E>
class [[nodiscard]] Expected<void, E> {
public:
    using value_type = void;
    using error_type = E;

    Expected() = default;
    template <class G>
    Expected(Unexpected<G> error) : error_(std::move(error).error()) {}  // NOLINT(implicit)

    bool has_value() const noexcept { return !error_.has_value(); }
    explicit operator bool() const noexcept { return has_value(); }
    void value() const {
        if (!has_value()) detail::bad_expected_access("value() on error");
    }
    E& error() & {
        if (has_value()) detail::bad_expected_access("error() on value");
        return *error_;
    }
    const E& error() const& {
        if (has_value()) detail::bad_expected_access("error() on value");
        return *error_;
    }

private:
    std::optional<E> error_;
};

}  // namespace ecpair
