/* SOES's build options for the size benchmark (bench/soes/size.sh), set like ecat's digital I/O
 * firmware (examples/stm32): no FoE, no EoE; both mailboxes 128 bytes at 0x1000/0x1080; the process
 * data right after them; one mapped object a way (the sample's 0x1600 and 0x1A00 map one each).
 * SPDX-License-Identifier: MIT OR Apache-2.0 */
#ifndef __ECAT_OPTIONS_H__
#define __ECAT_OPTIONS_H__

#include "cc.h"

#define USE_FOE          0
#define USE_EOE          0

#define MBXSIZE          128
#define MBXSIZEBOOT      128
#define MBXBUFFERS       3

#define MBX0_sma         0x1000
#define MBX0_sml         MBXSIZE
#define MBX0_sme         MBX0_sma+MBX0_sml-1
#define MBX0_smc         0x26
#define MBX1_sma         MBX0_sma+MBX0_sml
#define MBX1_sml         MBXSIZE
#define MBX1_sme         MBX1_sma+MBX1_sml-1
#define MBX1_smc         0x22

#define SM2_sma          0x1100
#define SM2_smc          0x24
#define SM2_act          1
#define SM3_sma          0x1180
#define SM3_smc          0x20
#define SM3_act          1

/* The sample maps 0x7000 and 0x6000, an UNSIGNED32 each. */
#define MAX_MAPPINGS_SM2 1
#define MAX_MAPPINGS_SM3 1
#define MAX_RXPDO_SIZE   4
#define MAX_TXPDO_SIZE   4

#endif /* __ECAT_OPTIONS_H__ */
