"""The MM4005's whole command set, by the manual's categories.

The manual's chapter 3 summary was not found; its list survives in a public Tcl GPIB
driver package 'mm4005' (2002), which names every two-letter command of the firmware
1.09 manual under the manual's category headings (in French), defining a few of them
and leaving the rest "uncoded". Every command page found later (BA, DV, FE, FF, GR, KD,
KI, KS, SS, TS, TX, XD, XF, XI, XP, DP, MS, TB, TH) sits in the group this list gives
it, so the list is taken as the set (confidence I). A command of this list that the
table does not model otherwise is known (never error A) and answers Q "not modelled",
naming its group: its page, and so its syntax and reply, were not found.
"""

from __future__ import annotations

from typing import Final

CATEGORIES: Final[tuple[tuple[str, str], ...]] = (
    ("mode selection", "CD CM MC ML MR RS MF MO"),
    ("motion and position control", "SE OR DH ZP PA PR AB ST"),
    ("motion parameters", "DA DV OA VB AC VA DF DP TH TP SD MV"),
    ("special motion parameters", "DM DO MH OH OL PB PE PI PS SH XH SY"),
    ("trace mode", "AQ GQ NQ SP SQ TM TQ TT XN XQ XS"),
    ("servo (PID) filter", "FE KD KI KP KS PW TF UF XD XF XI XP"),
    ("motor and stage set-up", "BA SC SF SN SL SR TA TC TL TN TR TU XB"),
    ("inputs and outputs", "AM CB FT RA RB RO SB SO TG YO YP YR"),
    ("programming", "AP CP EO EP EX LP MP QP SM XL XM XX"),
    ("sequencing and flow control", "DL IE JL KC OE RP RQ UH UL WA WE WF WG WH WK WL WP WS "
                                    "WT WY YE YG YL YN YW"),
    ("variables", "AS CS TY YA YB YC YD YF YK YM YQ YS YV YY"),
    ("display", "DS DY FB FC FD NP RD RE"),
    ("status", "ED TD TE TS TX TB VE MS"),
    ("trajectory definition", "AD AX AY CA CR CX CY EL FA LX LY MX MY NT"),
    ("trajectory execution", "ET VS VV WI WN"),
    ("trajectory definition aids", "AT LT XA XE XT XU XV"),
    ("master-slave", "FF GR SS"),
    ("trajectory synchronized pulses", "NB NE NI NN NS"),
)
"""(group, mnemonics); YP is listed under both I/O and variables there: kept under I/O."""

SOURCE: Final = "MM4005 command list by category, as a public Tcl GPIB driver 'mm4005' names it"

GROUP: Final[dict[str, str]] = {
    mnemonic: group for group, names in CATEGORIES for mnemonic in names.split()}
