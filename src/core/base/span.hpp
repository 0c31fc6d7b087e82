// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// A read-only view of elements stored one after another (an array, a vector, a span of the
// caller's), for interfaces that take a sequence without owning it. The core is C++17, where
// std::span does not exist yet; this is the part of it the core uses.
#pragma once

#include <cstddef>
#include <iterator>
#include <type_traits>
#include <utility>

namespace birdcage {

template <class T>
class Span {
public:
    using element_type = T;
    using value_type = std::remove_cv_t<T>;
    using iterator = T*;
    using reverse_iterator = std::reverse_iterator<T*>;

    constexpr Span() = default;
    constexpr Span(T* data, std::size_t size) : data_(data), size_(size) {}
    template <std::size_t N>
    constexpr Span(T (&array)[N]) : data_(array), size_(N) {}
    // Any container whose elements lie one after another: std::array, std::vector, std::span.
    template <class Container,
              class = std::enable_if_t<!std::is_same_v<std::decay_t<Container>, Span> &&
                                       std::is_convertible_v<decltype(std::declval<Container&>().data()), T*>>>
    constexpr Span(Container&& container) : data_(container.data()), size_(container.size()) {}

    constexpr T* begin() const { return data_; }
    constexpr T* end() const { return data_ + size_; }
    reverse_iterator rbegin() const { return reverse_iterator(end()); }
    reverse_iterator rend() const { return reverse_iterator(begin()); }
    constexpr T* data() const { return data_; }
    constexpr std::size_t size() const { return size_; }
    constexpr bool empty() const { return size_ == 0; }
    constexpr T& operator[](std::size_t i) const { return data_[i]; }
    constexpr T& front() const { return data_[0]; }
    constexpr T& back() const { return data_[size_ - 1]; }
    // The elements from `offset` on, at most `count` of them.
    constexpr Span subspan(std::size_t offset, std::size_t count = static_cast<std::size_t>(-1)) const {
        const std::size_t left = size_ - offset;
        return {data_ + offset, count < left ? count : left};
    }

private:
    T* data_ = nullptr;
    std::size_t size_ = 0;
};

}  // namespace birdcage
