# An empty value given as a separate argument (--width '') is refused like --width=, by every
# program (issue 20, item 8): one line naming the option, exit 2, nothing on stdout.
W=$TP_INPUTS/sai-weights.json
refuses 2 --says "--amplitude: empty value" -- af-field --amplitude ''
refuses 2 --says "--weights: empty value" -- af-field --weights '' --electrodes 2
refuses 2 --says "--max-current: empty value" -- optimize-weights --mode SAI --max-current ''
refuses 2 --stdin "$W" --says "--width: empty value" -- fiber-threshold --width ''
refuses 2 --stdin "$W" --says "--tolerance: empty value" -- fiber-threshold --tolerance ''
refuses 2 --stdin "$W" --says "--amplitude: empty value" -- make-pulse --amplitude ''
