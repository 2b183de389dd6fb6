; "A Simple VSL Task": three blocks; the tutor pushed the green block beyond the line and
; pulled the red one back. Blue is not part of the task.
(define (problem simple-push-pull)
  (:domain vsl-sp)
  (:objects red green blue - block)
  (:init
    (far red)
    (far blue))
  (:goal (and
    (far green)
    (not (far red)))))
