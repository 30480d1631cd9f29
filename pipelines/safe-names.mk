# Names that reach a shell: scene folder names, SCENE, SCENES, OUT, BUDGET.
# Make pastes them into recipes as they are, so a folder named
# `x$(touch${IFS}PWNED)` (from a data set or a CAD export) would run as a
# command, and `OUT='o ut'` would write to ./o and delete ./ut/verdict.json.
# Only letters, digits and _./+@- pass; anything else stops the run before
# any recipe, naming the value:
#   $(call require_safe,OUT)      (the variable's NAME: a value with a
#                                  comma would split a $(call)'s arguments)
# Pure make (no shell): commas become '?', then each allowed character is
# removed in turn; what is left is the unsafe rest. A name with a space
# arrives as two words and is refused as well. (`:` and `,` are refused
# here although the Snakefile takes them: in a make target a colon starts
# the prerequisites, and a comma splits function arguments.)
SAFE_NAME_COMMA := ,
SAFE_NAME_CHARS := a b c d e f g h i j k l m n o p q r s t u v w x y z \
  A B C D E F G H I J K L M N O P Q R S T U V W X Y Z 0 1 2 3 4 5 6 7 8 9 _ . / + @ -
unsafe_rest = $(if $(2),$(call unsafe_rest,$(subst $(firstword $(2)),,$(1)),$(wordlist 2,$(words $(2)),$(2))),$(1))
# "yes" when the variable named $(1) holds one safe word.
safe_var = $(and $($(1)),$(if $(word 2,$($(1))),,$(if $(call unsafe_rest,$(subst $(SAFE_NAME_COMMA),?,$($(1))),$(SAFE_NAME_CHARS)),,yes)))
require_safe = $(if $(call safe_var,$(1)),,$(error $(1)=$($(1)): only letters, digits and _./+@- are supported (the name reaches a shell)))
# A variable a pipeline cannot run without (SCENE, OUT, ...): stops the run
# when it is empty, saying what it should hold, and checks it as above.
#   $(call require_given,OUT,output/folder)
require_given = $(if $($(1)),,$(error $(1)=$(2) is required))$(call require_safe,$(1))

# Shell code for a recipe: stops it (exit 2, one line) when one of the
# pipeline's own paths under OUT, $(1) (already checked safe names), is a
# symbolic link. The pipeline writes, truncates and deletes these (its
# lock, times/*.seconds, temporaries); through a link that would happen
# outside OUT, to whatever file the link names. Refused, never followed:
#   @$(call refuse_links,$(OUT)/times $(OUT)/.path.csv.tmp)
refuse_links = for p in $(1); do if [ -L "$$p" ]; then \
  echo "pipeline: $$p is a symbolic link; the pipeline writes only its own files inside OUT and does not follow it (remove it)" >&2; \
  exit 2; fi; done
