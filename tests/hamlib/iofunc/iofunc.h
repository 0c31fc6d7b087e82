/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* Copyright (C) 2026 the birdcage authors */

/* The part of Hamlib's private src/iofunc.h that the in-tree port link
 * (src/hamlib/intree/hamlib_port.cpp) calls, for its test against the installed Hamlib, whose
 * libhamlib exports these functions but installs no header for them. In a Hamlib tree the
 * backend includes Hamlib's own. */
#ifndef BIRDCAGE_TEST_IOFUNC_H
#define BIRDCAGE_TEST_IOFUNC_H

#include <stddef.h>

#include <hamlib/rig.h>

int port_open(hamlib_port_t* p);
int port_close(hamlib_port_t* p, rig_port_t port_type);
int read_block(hamlib_port_t* p, unsigned char* rxbuffer, size_t count);
int write_block(hamlib_port_t* p, const unsigned char* txbuffer, size_t count);

#endif
