"""Keywords of the TrioBASIC help that atrio's token table predates, for fieldbus, set-up
and diagnostics: known by name, stored or read as 0, each with why it has no effect here.

Without an entry such a word was no keyword at all, so ``AIN_CONFIG(5) = 3`` or
``MS_BUS(0, 1)`` stopped a program with "Variable not defined" and ``IP_BIND_ADDRESS = 0``
silently made a local variable of a controller parameter. The words that act on motion,
inputs or set-up (ACCEL_FACTOR, FASTJERK, FORCE_ACCEL, MOVEADD, IN_FILTER ...) are in
NEWER_WORDS below, each modelled (the modules its note names) or "Not modelled" with why.

Row forms (keywords.py builds the entries; a word with a hand-written entry is skipped):

- ``S NAME w|r why``: a system parameter, writable or read only; ``A`` the same taking
  arguments (``NODE_AXIS_MAP(slot, node, i) = v``), each argument list keeping its value;
- ``F NAME min max why``: a function (returns 0); ``C NAME min max why``: a command.
"""

from __future__ import annotations

_BUS = "a fieldbus word: the emulator has no bus, slices or remote drives"
_FLASH = "an MC_CONFIG set-up of the controller's flash or boot, which the emulator has not"

HELP_WORDS = f"""\
S AUTOLOCK_SECONDS w the project lock's timer: the emulator has no project locking
S AUTO_PROFINET w {_BUS}
S BATTERY_LOW r the clock battery's state: there is no battery (reads 0, not low)
S DEBUG_LOG_MODE w {_FLASH}
S FLASH_TABLE_FIRST w {_FLASH}: TABLE is kept in memory only
S FLASH_TABLE_LAST w {_FLASH}: TABLE is kept in memory only
S FLASH_VR_FIRST w {_FLASH}: VRs are kept in memory only
S FLASH_VR_LAST w {_FLASH}: VRs are kept in memory only
S IP_BIND_ADDRESS w the local address of a program's network channels, which open no socket
S PCMCAT_PROC w the process of the PC-MCAT API program: there is no PC-MCAT connection
S PLOT_CALC w a reserved keyword (its page)
S SYSTEM_LOAD_AVG r the firmware's load: the emulator's servo cycle is one instant
S SYSTEM_WARNING r firmware warnings: the emulator reports none
S VP_MODE_PLC w {_FLASH}
A AIN_CONFIG w the analogue input's electrical mode: the world's inputs have one range
A AOUT_CONFIG w the analogue output's electrical mode: the world's outputs have one range
A DV_CONTROLWORD w {_BUS}
A DV_OUT w {_BUS}
A DV_IN r {_BUS}
A DV_STATUSWORD r {_BUS}
A MS_BUS_CONFIG w {_BUS}
A NODE_AXIS_MAP w {_BUS}
A NW_NODE_PROFILE w {_BUS}
F CHANNEL_TRANSACT 1 16 a network channel's transaction: program channels open no socket
F DEBUG_LOG 0 2 the firmware's event log: the emulator logs no firmware events
F MS_BUS 1 16 {_BUS}
F MS_BUS_IO 1 16 {_BUS}
F REGISTER_KEYWORD 4 4 the open architecture's own keywords are not emulated
F REGISTER_MOVE 5 5 the open architecture's own moves are not emulated
C AXISLIST 0 0 the list of active axes: every axis here is always present (prints nothing)
C DV_MAP 0 0 {_BUS} (prints nothing)
C TOKENTABLE 0 0 the token list a host downloads: its numbered tags are not in the pages
"""

NEWER_NOTE = "Known from its help page, not the MC405's token table, which predates it (D)."
_REMOTE = ("a remote (EtherCAT/RTEX) drive's word: the MC405 emulated here drives no "
           "remote drive")
_RESERVED = "a reserved keyword: its page gives no behaviour"
_VP56 = "VP_MODE 5 and 6 look-ahead tuning"

NEWER_WORDS = f"""\
P ACCEL_FACTOR w 1 0 1 =In VP_MODE 5 and 6 the moves' ACCEL and DECEL are taken times it
    (C: its page); written while a move runs, as ACCEL is (re-planned from where it is,
    respeed.py: D, as its page's example turns a potentiometer); ignored in VP_MODE 0 (C).
    0 leaves the moves running as they are and refuses new ones, as ACCEL 0 (D).
P AXIS_BLENDING w 1 0 4 -the emulator's SP moves always blend as its power-up 1 (Low, see
    profiles_sp.py); 0, 2, 3 and 4 are stored, not applied
P AXIS_ENABLE_OVERRIDE w 0 -1 1 =ON enables the axis's drive even with WDOG and AXIS_ENABLE
    OFF (C: its page): moves load and a servo axis's loop closes (drive.py); a servo axis
    still needs SERVO ON, and the open-loop DAC output (SERVO OFF) still needs WDOG (D).
    Power-up OFF (C).
P CLOSE_WINB w 0 -1e15 1e15 =Where the second registration window closes (user units): REGIST
    modes 20 and 21 with window 5 take only edges inside OPEN_WINB..CLOSE_WINB, window 6 only
    outside (C: REGIST page; as DPOS reads, REP_DIST folded, as OPEN_WIN); windows 1/2 keep
    OPEN_WIN..CLOSE_WIN.
P DRIVE_BRAKE_OUTPUT w -1 -1 1023 -it hands an output to an EtherCAT slim drive's brake;
    {_REMOTE} (power-up -1 none, D)
P DRIVE_NEG_TORQUE w 0 -32768 32767 -{_REMOTE} (an INT16 in drive units)
P DRIVE_POS_TORQUE w 0 -32768 32767 -{_REMOTE} (an INT16 in drive units)
P DRIVE_REP_DIST w 4294967296 0 4294967296 -{_REMOTE} (power-up 2^32, the page's roll-over)
P FASTJERK w 0 0 1e15 =The jerk of a stop (CANCEL, RAPIDSTOP, a limit) in VP_MODE 5 and 6,
    user units/s^3: used when above JERK, else JERK (C: FASTJERK page); 0 not used (C).
    Ignored in VP_MODE 0 (C). Assigned SRAMP (not 0) in VP_MODE 6 takes over as FASTDEC/SRAMP
    (C); the emulator takes SRAMP 0 as not assigned (D).
P FORCE_ACCEL w -1 -1 1e15 =An SP move's own acceleration (MOVESP, MOVEABSSP, MOVECIRCSP,
    MHELICALSP), user units/s^2, taken as it loads in place of ACCEL (C: FORCE_ACCEL page);
    -1 (power-up, C) or 0 (D): ACCEL. Merged SP moves each ramp up at their own (D).
    MOVEADD's demand (MOVEADD is not modelled: see its entry).
P FORCE_DECEL w -1 -1 1e15 =An SP move's own deceleration, user units/s^2, in place of DECEL
    (C: FORCE_DECEL page); -1 or 0: DECEL. A run of merged moves ramps down at the first
    one's (D, as DECEL).
P FORCE_JERK w -1 -1 1e15 =An SP move's own jerk in VP_MODE 5 and 6, user units/s^3, in place
    of JERK (C: FORCE_JERK page, AXIS_BLENDING: not in VP_MODE 0); -1 or 0: JERK; over
    SRAMP's ACCEL/SRAMP in VP_MODE 6 too (D).
P FWD_START w 0 -1e15 1e15 =1 with FWD_JOG at -1 jogs the axis forward (MTYPE 14) as a
    low jog input would: at JOGSPEED (SPEED with FAST_JOG low), from idle, ramping down at
    DECEL when it is set to anything else (C: FWD_START page's table; the jog's rules, D:
    see FWD_JOG); with FWD_JOG naming an input it has no function (C) (jogs.py).
P JERK_FACTOR w 1 0 1 =In VP_MODE 5 and 6 the moves' JERK is taken times it (C: its
    page), as a move loads (D: the page does not say how a change reaches a move running);
    ignored in VP_MODE 0 (C); 0: no jerk limit, as JERK 0 (D).
P MOVE_COUNT_INC w 1 -1e15 1e15 =What MOVE_COUNT changes by for each move that becomes the
    running one (C: MOVE_COUNT_INC page; 0 leaves it, negative counts down). Power-up 1 (D:
    MOVE_COUNT's own counting by one).
P MOVE_FORCE_ACCEL r -1 -1 1e15 =The FORCE_ACCEL the running move loaded with (C: its page):
    an SP move's, on every axis of its group; -1 with none running or a plain move (D).
P MOVE_FORCE_DECEL r -1 -1 1e15 =The FORCE_DECEL the running move loaded with (C: its page):
    an SP move's, on every axis of its group; -1 with none running or a plain move (D).
P MOVE_FORCE_SPEED r -1 -1 1e15 =The FORCE_SPEED the running move loaded with (C: its page):
    an SP move's, on every axis of its group; -1 with none running or a plain move (D).
P MPOS_DELAY w 0 -1e15 1e15 -{_RESERVED}
P MPOS_PRE_COMP w 0 -1e15 1e15 -{_RESERVED}
P OPEN_WINB w 0 -1e15 1e15 =Where the second registration window opens (user units): see
    CLOSE_WINB (C: OPEN_WINB page).
P REMAIN_TIME r 0 0 1e15 =The seconds until the moves the axis holds are done (C: its page):
    the running move's end less now plus each single-axis move buffered behind it from rest
    at the rates it loaded with, in whole servo cycles (D); a buffered multi-axis run counts
    once it starts, links and moves without an end add nothing (D; profile_readings.py).
P REV_START w 0 -1e15 1e15 =As FWD_START, in reverse (MTYPE 15) with REV_JOG at -1 (C:
    REV_START page).
P SPEED_FACTOR w 1 0 1 =In VP_MODE 5 and 6 the moves' SPEED is taken times it (C: its
    page; SP moves keep FORCE_SPEED, see LOOKAHEAD_FACTOR); written while a move runs, as
    SPEED is: re-planned from where it is toward the new speed (respeed.py, D); ignored in
    VP_MODE 0 (C). 0 leaves the moves running as they are and refuses new ones (D).
P STOPPING_DISTANCE r 0 0 1e15 =How far the axis runs to rest if its move is cancelled now
    (C: its page; D: at the rates a CANCEL uses here, the move's DECEL with its SRAMP or JERK
    and FASTJERK, from the profile speed, the acceleration starting from 0): v^2 / 2 DECEL
    for a linear ramp; along the path for a multi-axis move; what is left of a stop running;
    0 at rest and on links (D; profile_readings.py).
P VP_DEMAND_ACCEL r 0 -1e15 1e15 =The profiler's demand acceleration (C: its page), user
    units/s^2: the ACCEL (an SP move's FORCE_ACCEL) the move now running loaded with (D: not
    the acceleration now, VP_ACCEL reads that), in the base axis's user units on every axis
    of its group (D); 0 with no move running, on links and CAMs (D; profile_readings.py).
P VP_DEMAND_DECEL r 0 -1e15 1e15 =The profiler's demand deceleration (C: its page): the DECEL
    (FORCE_DECEL) the running move loaded with, as VP_DEMAND_ACCEL (D).
P VP_DEMAND_JERK r 0 -1e15 1e15 =The profiler's demand jerk (C: its page), user units/s^3:
    the jerk limit the running move loaded with in VP_MODE 5 and 6 (JERK times JERK_FACTOR,
    an SP move's FORCE_JERK), 0 in VP_MODE 0, as VP_DEMAND_ACCEL (D).
P VP_DEMAND_SPEED r 0 -1e15 1e15 =The profiler's demand speed (C: its page), user units/s:
    the speed the running move loaded with as the profiler was given it (SPEED or FORCE_SPEED
    after SPEED_FACTOR, V_LIMIT and INTERP_FACTOR; SPEED written mid-move re-plans it), not
    the speed now (VP_SPEED); 0 while CANCEL or RAPIDSTOP ramps it to rest; as
    VP_DEMAND_ACCEL otherwise (D).
P VP_ERROR r 0 0 10 =Reads 0: the error of VP_MODE 6's profiler, which the emulator's profiler
    never raises (its codes are for a VPU fed bad demands, which the table's ranges refuse
    first) (D).
P VP_OPTIONS w 0 0 63 -VP_MODE 6 tuning (buffer depth, forced-demand binding, processor use):
    the emulator has one jerk profile (see VP_MODE)
P V_LIMIT w 0 -1e15 1e15 =An axis's speed limit, user units/s (<= 0 none): a move loaded
    with it is slowed so that no axis with a limit runs faster: a line at the vector speed
    x |d_i| / L within each limit, an arc (MOVECIRC, MHELICAL...) at the lowest limit of its
    axes (C: V_LIMIT page); taken when the move loads (D); ignored in VP_MODE 5 (C). An SP
    move's top speed is cut the same, its STARTMOVE/ENDMOVE speeds are not (D).
Y GTASIZE r 0 0 0 -the global target array of the robot system (GTA), not modelled: reads 0
    (no element)
Y IN_DEBOUNCE w 0 0 1e6 =IN reads an input's new level only once its voltage has held it for
    IN_DEBOUNCE servo cycles, a shorter glitch never (C: its page); registration is not
    affected (C), nor limits, jogs and feed hold (D: the page names IN); power-up 0, none
    (D); INVERT_IN applies after it (D) (debounce.py).
K COMBINE_AXES 2 2 =COMBINE_AXES(axis_a, axis_b) AXIS(n): axis n's DPOS is COMBINE_CONTROL's
    function of the two axes' positions, every servo tick (C: its page); a linked move of
    axis n as COMPENSATE_XY (buffered, ended by CANCEL, MTYPE 26: D), absolute (D), the
    sources' demand read for MPOS too (D) (combine.py).
K COMBINE_CONTROL 3 7 =COMBINE_CONTROL(mode, source_1, source_2[, n1, d1, n2, d2]) AXIS(n):
    0 sum, 1 difference, 3 average of the sources times n/d; COMBINE_CONTROL(2, offset_1,
    offset_2) the hypotenuse of the offset sources (C: its page). Kept for the next
    COMBINE_AXES, taken at once by a running one (D); none given: the plain sum (D); a 0
    denominator or another mode: Parameter out of range (D) (combine.py).
K COMPENSATE_ENC 0 0 -{_RESERVED}
K MOVEABSSPCONT 1 1 -its page gives no behaviour ("under development")
K MOVEADD 1 1 -a move superimposed on the running one (C: its page; ADDAX of a virtual
    axis's MOVE does that and is modelled). The page leaves open what its "own S-ramped VPU"
    ramps with when FORCE_JERK and JERK are unset (VP_MODE 0 has no jerk), what MOVEADD does
    on an idle axis, and whether a second MOVEADD adds to or queues behind the first
K MOVESPCONT 1 1 -its page gives no behaviour ("under development")
K MOVETEST 1 9 =MOVETEST(1, dist0, accel0, speed0, dwell0, dist1, accel1, speed1, dwell1)
    cycles MOVE(dist0), a dwell of dwell0 ms, MOVE(-dist1), dwell1 ms, each move at its own
    speed and acceleration (C: its page; the deceleration the acceleration, dist1 the
    distance back, the axis's SPEED/ACCEL/DECEL left as they were: D); MOVETEST(0) ends it
    after the second move, CANCEL/RAPIDSTOP at once (C) (movetest.py).
G IN_FILTER 2 3 -the page: filtering exists only on MotionPLC controllers and slices, which
    the MC405 is not
G SET_MOTION 2 5 =SET_MOTION(axis, speed[, accel[, decel[, jerk]]]) writes SPEED, ACCEL, DECEL
    and JERK of the axis named (C: SET_MOTION page); each value range-checked as its
    parameter, nothing written when one is refused (D).
G SET_MOTIONSP 2 9 =SET_MOTIONSP(axis, force_speed[, startmove_speed[, endmove_speed[,
    force_accel[, force_decel[, force_jerk[, force_ramp[, force_dwell]]]]]]]) writes those
    parameters of the axis named (C: SET_MOTIONSP page); each range-checked, nothing written
    when one is refused (D).
"""
"""Words of the help that are newer than the MC405's token table and act on motion, inputs
or set-up. Row forms: ``P NAME w|r default low high note`` an axis parameter, ``Y`` the same
for a system parameter, ``K NAME min max note`` an axis command (AXIS(n) allowed), ``G``
a command without AXIS; an indented line goes on the row above. A note starting ``=`` is
what the emulator does; ``-`` is why it is not modelled."""
