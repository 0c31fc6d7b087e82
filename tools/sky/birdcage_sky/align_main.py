# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors
"""placeholder"""
def main(argv, version="", started=None):
    return 0
